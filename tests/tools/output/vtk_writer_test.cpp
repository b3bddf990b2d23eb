// ParaView output: the files of an elastic scene read back through a small XML parser (well-formed,
// counts right, the tip displacement equal to the probe's), the stress of finite-strain bodies (their
// law's Cauchy stress: none under a rigid motion, the closed form under a stretch, a bounded one in the
// tied pendulum's swing), the contact writer on hand-made states, and no ParaView files for lumped
// scenes or for a run that stopped.
#include "tools/output/paraview_series.h"
#include "tools/output/vtk_writer.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"
#include "fem/mesh_generators.h"
#include "tests/tools/output/vtu_reader.h"
#include "tests/tools/output/xml_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace csim {
namespace {

namespace fs = std::filesystem;
using test_xml::XmlElement;
using test_xml::XmlReader;

const std::string kBar = CSIM_SOURCE_DIR "/scenes/fe-free-vibration/scene.yaml";
const std::string kIncline = CSIM_SOURCE_DIR "/scenes/incline/scene.yaml";

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot read");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

XmlElement read_xml(const fs::path& path) { return XmlReader(read_text(path)).document(); }
// A .vtu in any encoding, its appended arrays decoded into their text (vtu_reader.h).
XmlElement read_vtu(const fs::path& path) { return test_vtu::read_vtu(read_text(path)).root; }

const XmlElement& piece_of(const XmlElement& vtu) { return vtu.child("UnstructuredGrid").child("Piece"); }

// probes.csv as a header and rows of numbers.
struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  int column(const std::string& name) const {
    for (std::size_t i = 0; i < columns.size(); ++i)
      if (columns[i] == name) return static_cast<int>(i);
    throw std::runtime_error("no column " + name);
  }
};

Table read_csv(const fs::path& path) {
  std::istringstream in(read_text(path));
  Table table;
  std::string line, cell;
  std::getline(in, line);
  for (std::istringstream header(line); std::getline(header, cell, ',');) table.columns.push_back(cell);
  while (std::getline(in, line)) {
    table.rows.emplace_back();
    for (std::istringstream row(line); std::getline(row, cell, ',');) table.rows.back().push_back(std::stod(cell));
  }
  return table;
}

fs::path fresh_directory(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / name;
  fs::remove_all(dir);
  return dir;
}

std::vector<VtkEncoding> encodings() {
  std::vector<VtkEncoding> out{VtkEncoding::ascii, VtkEncoding::binary};
  if (vtk_compression_available()) out.push_back(VtkEncoding::zlib);
  return out;
}
const std::vector<VtkEncoding> kEncodings = encodings();

// ---- the writers on plain data --------------------------------------------------------------------

TEST(VtkWriter, XmlReaderRejectsMalformedText) {
  for (const char* bad : {"<a><b></a></b>", "<a x=1/>", "<a x=\"1\"y=\"2\"/>", "<a>", "<a></a><b/>", "<a>&bad;</a>"})
    EXPECT_THROW(XmlReader(bad).document(), std::runtime_error) << bad;
  EXPECT_NO_THROW(XmlReader("<?xml version=\"1.0\"?>\n<a x='1'><b y=\"&amp;\"/>text</a>\n").document());
  EXPECT_THROW(XmlReader("<!-- a -- b --><a/>").document(), std::runtime_error);
  XmlReader commented("<?xml version=\"1.0\"?>\n<!-- one -->\n<!--two--><a/>");
  EXPECT_NO_THROW(commented.document());
  EXPECT_EQ(commented.prolog_comments(), (std::vector<std::string>{" one ", "two"}));
}

// A description with "--" or a trailing '-' still gives a well-formed comment.
TEST(VtkWriter, HeaderCommentsStayWellFormed) {
  Mesh mesh;
  mesh.element_type = ElementType::quad4;
  mesh.nodes.assign(4, Eigen::Vector3d::Zero());
  mesh.elements.push_back({0, 1, 2, 3});
  ElementFields fields;
  fields.stress.push_back(Stress::Zero());
  fields.stress_description = "a -- b ---";
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(8);
  XmlReader reader(fe_body_vtu(mesh, u, u, fields, 0.0, VtkEncoding::ascii));
  EXPECT_NO_THROW(reader.document());
  ASSERT_FALSE(reader.prolog_comments().empty());
  EXPECT_EQ(reader.prolog_comments()[0], " stress: a - - b - - - ");
}

TEST(VtkWriter, VonMisesOfUniaxialAndPureShear) {
  Stress uniaxial, shear;
  uniaxial << 3.0, 0, 0, 0, 0, 0;
  shear << 0, 0, 0, 2.0, 0, 0;
  EXPECT_DOUBLE_EQ(von_mises(uniaxial), 3.0);
  EXPECT_DOUBLE_EQ(von_mises(shear), 2.0 * std::sqrt(3.0));
}

ActiveContact contact_at(double x, ContactStatus status, const Eigen::Vector3d& impulse) {
  ActiveContact c;
  c.point.point_a = Eigen::Vector3d(x, 0.0, 0.0);
  c.point.point_b = Eigen::Vector3d(x, -2e-6, 0.0);  // gap −2 µm along n = −e_y
  c.point.normal = -Eigen::Vector3d::UnitY();
  c.point.gap = -2e-6;
  c.impulse = impulse;
  c.status = status;
  return c;
}

TEST(VtkWriter, ContactsCarryStatusImpulseNormalAndGap) {
  const std::vector<ActiveContact> contacts{contact_at(0.5, ContactStatus::stick, {10.0, 1.5, 0.0}),
                                            contact_at(2.0, ContactStatus::slip, {20.0, -6.0, 0.0})};
  for (const VtkEncoding encoding : kEncodings) {
  SCOPED_TRACE(static_cast<int>(encoding));
  const XmlElement piece = piece_of(test_vtu::read_vtu(contacts_vtu(contacts, 0.25, encoding)).root);
  EXPECT_EQ(piece.attributes.at("NumberOfPoints"), "2");
  EXPECT_EQ(piece.attributes.at("NumberOfCells"), "2");
  const XmlElement& data = piece.child("PointData");
  EXPECT_EQ(data.array("status").attributes.at("type"), "Int32");
  EXPECT_EQ(data.array("status").numbers(), (std::vector<double>{1, 2}));
  EXPECT_EQ(data.array("impulse").numbers(), (std::vector<double>{10.0, 1.5, 0.0, 20.0, -6.0, 0.0}));
  EXPECT_EQ(data.array("normal").numbers(), (std::vector<double>{0, -1, 0, 0, -1, 0}));
  EXPECT_EQ(data.array("gap").numbers(), (std::vector<double>{-2e-6, -2e-6}));
  EXPECT_EQ(piece.child("Points").child("DataArray").numbers(),
            (std::vector<double>{0.5, -1e-6, 0, 2.0, -1e-6, 0}));  // midpoints of A's and B's points
  const XmlElement& cells = piece.child("Cells");
  EXPECT_EQ(cells.array("connectivity").numbers(), (std::vector<double>{0, 1}));
  EXPECT_EQ(cells.array("offsets").numbers(), (std::vector<double>{1, 2}));
  EXPECT_EQ(cells.array("types").numbers(), (std::vector<double>{1, 1}));  // VTK_VERTEX
  }
}

TEST(VtkWriter, NoContactsGiveAValidEmptyGrid) {
  for (const VtkEncoding encoding : kEncodings) {
    const XmlElement vtu = test_vtu::read_vtu(contacts_vtu({}, 0.0, encoding)).root;
    const XmlElement& piece = piece_of(vtu);
    EXPECT_EQ(piece.attributes.at("NumberOfPoints"), "0");
    EXPECT_EQ(piece.attributes.at("NumberOfCells"), "0");
    EXPECT_TRUE(piece.child("PointData").array("status").numbers().empty());
    EXPECT_TRUE(piece.child("Cells").array("offsets").numbers().empty());
  }
}

TEST(VtkWriter, CollectionListsFilesWithTheirTimes) {
  const XmlElement pvd = XmlReader(pvd_collection({{0.0, "a_000000.vtu"}, {1e-5, "a&b_000001.vtu"}})).document();
  ASSERT_EQ(pvd.attributes.at("type"), "Collection");
  const auto& sets = pvd.child("Collection").children;
  ASSERT_EQ(sets.size(), 2u);
  EXPECT_EQ(std::stod(sets[1].attributes.at("timestep")), 1e-5);
  EXPECT_EQ(sets[1].attributes.at("file"), "a&amp;b_000001.vtu");  // escaped in the attribute
}

TEST(VtkWriter, CellTypesAndThreeComponentsForEachElementType) {
  // One element of each type; 3D displacements keep their z, plane ones get z = 0.
  for (const auto& [type, cell, d] : {std::tuple{ElementType::quad4, 9, 2}, std::tuple{ElementType::quad8, 23, 2},
                                      std::tuple{ElementType::hexa8, 12, 3}}) {
    Mesh mesh;
    mesh.element_type = type;
    const int n = nodes_per_element(type);
    mesh.nodes.assign(n, Eigen::Vector3d::Zero());
    mesh.elements.push_back({});
    for (int i = 0; i < n; ++i) mesh.elements[0].push_back(i);
    const Eigen::VectorXd u = Eigen::VectorXd::LinSpaced(d * n, 1.0, d * n);
    ElementFields fields;
    fields.stress.push_back(Stress::Zero());
    for (const VtkEncoding encoding : kEncodings) {
      const XmlElement piece = piece_of(test_vtu::read_vtu(fe_body_vtu(mesh, u, u, fields, 0.0, encoding)).root);
      EXPECT_EQ(piece.child("Cells").array("types").numbers(), std::vector<double>{double(cell)});
      const std::vector<double> written = piece.child("PointData").array("displacement").numbers();
      ASSERT_EQ(written.size(), 3u * n);
      EXPECT_EQ(written[3 * (n - 1) + 1], d * (n - 1) + 2.0);              // y of the last node
      EXPECT_EQ(written[3 * (n - 1) + 2], d == 3 ? 3.0 * n : 0.0);         // its z
    }
  }
}

// ---- a whole run ------------------------------------------------------------------------------------

TEST(VtkWriter, ElasticBarFramesMatchTheProbes) {
  const fs::path dir = fresh_directory("csim_vtk_bar");
  const auto scene = load_scene(kBar, {"time.end=1e-4"});
  const RunReport report = run_scene(*scene, {dir.string()});
  const Table probes = read_csv(dir / "probes.csv");
  ASSERT_EQ(probes.rows.size(), 11u);  // t = 0 and every 1e-5 s

  for (const char* series : {"bar", "contacts"}) {
    const XmlElement pvd = read_xml(dir / "paraview" / (std::string(series) + ".pvd"));
    const auto& sets = pvd.child("Collection").children;
    ASSERT_EQ(sets.size(), probes.rows.size()) << series;
    for (std::size_t k = 0; k < sets.size(); ++k) {
      const double t = std::stod(sets[k].attributes.at("timestep"));
      EXPECT_EQ(t, report.sample_times[k]) << series;
      EXPECT_NEAR(t, probes.rows[k][0], 1e-12 * 1e-4) << series;  // probes.csv holds 15 digits
      if (k > 0) {
        EXPECT_GT(t, std::stod(sets[k - 1].attributes.at("timestep"))) << series;
      }
      EXPECT_TRUE(fs::exists(dir / "paraview" / sets[k].attributes.at("file"))) << series;
    }
  }

  const int tip_column = probes.column("tip");
  for (std::size_t k = 0; k < probes.rows.size(); ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "bar_%06zu.vtu", k);
    const XmlElement piece = piece_of(read_vtu(dir / "paraview" / name));
    ASSERT_EQ(piece.attributes.at("NumberOfPoints"), "63") << name;  // 21 × 3 nodes
    ASSERT_EQ(piece.attributes.at("NumberOfCells"), "40") << name;
    const std::vector<double> u = piece.child("PointData").array("displacement").numbers();
    const std::vector<double> v = piece.child("PointData").array("velocity").numbers();
    const std::vector<double> x = piece.child("Points").child("DataArray").numbers();
    ASSERT_EQ(u.size(), 3u * 63) << name;
    ASSERT_EQ(v.size(), 3u * 63) << name;
    EXPECT_EQ(piece.child("CellData").array("stress").numbers().size(), 6u * 40) << name;
    EXPECT_EQ(piece.child("CellData").array("von_mises").numbers().size(), 40u) << name;
    EXPECT_EQ(piece.child("CellData").array("pressure").numbers().size(), 40u) << name;
    EXPECT_THROW(piece.child("CellData").array("green_lagrange_strain"), std::runtime_error) << name;
    const std::vector<double> types = piece.child("Cells").array("types").numbers();
    EXPECT_EQ(types, std::vector<double>(40, 9.0)) << name;  // VTK_QUAD
    EXPECT_EQ(piece.child("Cells").array("connectivity").numbers().size(), 4u * 40) << name;

    int tip = -1;
    for (int i = 0; i < 63; ++i)
      if (x[3 * i] == 1.0 && x[3 * i + 1] == 0.0) tip = i;
    ASSERT_GE(tip, 0);
    // The file holds u itself; the probe is (x_tip + u) − x_tip, rounded to an ulp of x_tip = 1 m
    // (2.2e-16 m, 2e-12 of u at these times): allow that on top of 1e-12 relative.
    const double probe = probes.rows[k][tip_column];
    EXPECT_NEAR(u[3 * tip], probe, 1e-12 * std::abs(probe) + std::numeric_limits<double>::epsilon() * x[3 * tip])
        << name;
    if (k == 0) {  // uniform initial velocity 1 m/s along x, except the clamped nodes at x = 0
      for (int i = 0; i < 63; ++i) EXPECT_EQ(v[3 * i], x[3 * i] == 0.0 ? 0.0 : 1.0) << "node " << i;
    }
  }
  ASSERT_NE(report.samples.back()[tip_column - 1], 0.0);  // the last frame checks a moving tip

  const test_vtu::VtuFile bar_file = test_vtu::read_vtu(read_text(dir / "paraview" / "bar_000010.vtu"));
  EXPECT_TRUE(bar_file.appended);  // the default encoding: binary
  EXPECT_FALSE(bar_file.compressed);
  ASSERT_FALSE(bar_file.comments.empty());
  EXPECT_NE(bar_file.comments[0].find("stress: linear elastic stress"), std::string::npos);

  const XmlElement contacts = piece_of(read_vtu(dir / "paraview" / "contacts_000010.vtu"));
  EXPECT_EQ(contacts.attributes.at("NumberOfPoints"), "0");  // the bar touches nothing
}

// A neo-Hookean body in a World of its own (no fixed dofs: q is the displacement of every dof), one
// frame per motion: u = (F − I) X + c.
struct FiniteStrainWorld {
  World world;
  const FeBody* body = nullptr;
  explicit FiniteStrainWorld(Mesh mesh, const HyperelasticMaterial& material) {
    world.dimension = mesh.dimension();
    const int dofs = mesh.dof_count();
    auto fe = std::make_unique<FeBody>(std::move(mesh), FiniteStrainLaw{material, FiniteStrainFormulation::standard}, 0.1, true,
                                       std::vector<std::pair<int, int>>{});
    body = fe.get();
    BodyInstance instance;
    instance.name = "block";
    instance.body = std::move(fe);
    instance.reference_position = instance.initial_position = instance.initial_velocity = Vector::Zero(dofs);
    world.bodies.push_back(std::move(instance));
    world.finalize_layout();
  }
  State state_of(const Eigen::Matrix3d& F, const Eigen::Vector3d& c) const {
    const Mesh& mesh = body->mesh();
    const int d = mesh.dofs_per_node();
    State state;
    state.q.resize(world.position_size);
    state.v.setZero(world.velocity_size);
    for (int i = 0; i < static_cast<int>(mesh.nodes.size()); ++i)
      state.q.segment(d * i, d) = ((F - Eigen::Matrix3d::Identity()) * mesh.nodes[i] + c).head(d);
    return state;
  }
};

// Frame 0: a rigid motion (90 degrees and a translation), which the linear law of the small strain
// showed as a stress of order E (issue 29); the body's own law writes none. Frame 1: a plane-strain
// stretch F = diag(a, 1, 1), whose neo-Hookean Cauchy stress σ = [μ (b − I) + λ ln J I] / J is
// σxx = [μ (a² − 1) + λ ln a] / a, σyy = σzz = λ ln a / a: von Mises |σxx − σyy| = μ (a² − 1) / a,
// pressure −[μ (a² − 1) + 3λ ln a] / (3a). Every array has one tuple per element or node.
TEST(VtkWriter, FiniteStrainBodyWritesTheCauchyStressOfItsLaw) {
  const HyperelasticMaterial material = neo_hookean(2e6, 0.3, 1000.0);
  const double lambda = material.lambda, mu = material.mu, modulus = lambda + 2.0 * mu;  // Pa
  const double a = 1.25;
  for (Mesh mesh : {rectangle_mesh(2.0, 1.0, 4, 2, ElementType::quad4, {0.0, {1.0, 2.0, 0.0}}),
                    box_mesh(2.0, 1.0, 1.0, 2, 2, 2, {0.0, {1.0, 2.0, 3.0}})}) {
    const fs::path dir = fresh_directory("csim_vtk_finite_strain");
    const std::size_t nodes = mesh.nodes.size(), cells = mesh.elements.size();
    const std::string type = to_string(mesh.element_type);
    const FiniteStrainWorld block(std::move(mesh), material);
    const Eigen::Vector3d axis = block.world.dimension == 3 ? Eigen::Vector3d(1, -2, 2).normalized() : Eigen::Vector3d::UnitZ();
    {
      ParaviewSeries series(block.world, dir.string(), VtkEncoding::ascii);
      series.write_frame(block.world, block.state_of(Eigen::AngleAxisd(M_PI / 2, axis).toRotationMatrix(), {0.3, -0.7, 0.2}), 0.0);
      series.write_frame(block.world, block.state_of(Eigen::Vector3d(a, 1.0, 1.0).asDiagonal(), Eigen::Vector3d::Zero()), 1.0);
      series.finish();
    }
    for (int frame : {0, 1}) {
      const fs::path file = dir / "paraview" / ("block_00000" + std::to_string(frame) + ".vtu");
      XmlReader reader(read_text(file));
      const XmlElement piece = piece_of(reader.document());
      ASSERT_GE(reader.prolog_comments().size(), 3u) << type;
      EXPECT_NE(reader.prolog_comments()[0].find("Cauchy stress sigma = P F^T / J of the neo_hookean law"), std::string::npos)
          << reader.prolog_comments()[0];
      EXPECT_EQ(piece.child("PointData").array("displacement").numbers().size(), 3 * nodes) << type;
      const XmlElement& data = piece.child("CellData");
      const std::vector<double> stress = data.array("stress").numbers(), equivalent = data.array("von_mises").numbers(),
                                pressure = data.array("pressure").numbers(),
                                strain = data.array("green_lagrange_strain").numbers();
      ASSERT_EQ(stress.size(), 6 * cells) << type;
      ASSERT_EQ(equivalent.size(), cells) << type;
      ASSERT_EQ(pressure.size(), cells) << type;
      ASSERT_EQ(strain.size(), 6 * cells) << type;
      for (std::size_t e = 0; e < cells; ++e) {
        if (frame == 0) {
          for (int k = 0; k < 6; ++k) {
            EXPECT_LT(std::abs(stress[6 * e + k]), 1e-13 * modulus) << type << " element " << e;
            EXPECT_LT(std::abs(strain[6 * e + k]), 1e-14) << type << " element " << e;
          }
          continue;
        }
        const double sxx = (mu * (a * a - 1.0) + lambda * std::log(a)) / a, syy = lambda * std::log(a) / a;
        const std::vector<double> expected{sxx, syy, syy, 0.0, 0.0, 0.0};
        for (int k = 0; k < 6; ++k) EXPECT_NEAR(stress[6 * e + k], expected[k], 1e-12 * sxx) << type << " " << k;
        EXPECT_NEAR(equivalent[e], mu * (a * a - 1.0) / a, 1e-12 * sxx) << type;
        EXPECT_NEAR(pressure[e], -(mu * (a * a - 1.0) + 3.0 * lambda * std::log(a)) / (3.0 * a), 1e-12 * sxx) << type;
        EXPECT_NEAR(strain[6 * e], (a * a - 1.0) / 2.0, 1e-14) << type;  // Exx; the others 0
      }
    }
  }
}

// The tied pendulum (a neo-Hookean bar, E = 1e10 Pa, swinging as a near-rigid body) read back frame by
// frame: the stress is the swing's, not the rotation's. Beam estimate of the largest one: at the
// release the hub's inertia takes the root moment I_hub α = 14.3 N·m (α = m g d / I_O = 14.3 rad/s²),
// 6 M / b² = 8.6e3 Pa, doubled by the sudden load; at the bottom the spin adds the tension
// ρ ω² L² / 2 = 1.4e4 Pa (ω = 5.34 rad/s): 3.1e4 Pa = 3.1e-6 E. The bound 1e-5 E leaves room for the
// tied corners; the linear law of the small strain wrote 1.5 E there (issue 29).
TEST(VtkWriter, TiedPendulumFramesShowTheSwingNotTheRotation) {
  const fs::path dir = fresh_directory("csim_vtk_tied_pendulum");
  const auto scene = load_scene(CSIM_SOURCE_DIR "/scenes/tied-pendulum/scene.yaml", {});
  const RunReport report = run_scene(*scene, {dir.string()});
  const XmlElement pvd = read_xml(dir / "paraview" / "bar.pvd");
  const auto& sets = pvd.child("Collection").children;
  ASSERT_EQ(sets.size(), report.sample_times.size());
  double largest = 0.0;
  for (const XmlElement& set : sets) {
    const XmlElement piece = piece_of(read_vtu(dir / "paraview" / set.attributes.at("file")));
    const XmlElement& data = piece.child("CellData");
    ASSERT_EQ(data.array("stress").numbers().size(), 6u * 40);  // 20 × 2 quad4
    ASSERT_EQ(data.array("green_lagrange_strain").numbers().size(), 6u * 40);
    ASSERT_EQ(data.array("pressure").numbers().size(), 40u);
    const std::vector<double> equivalent = data.array("von_mises").numbers();
    ASSERT_EQ(equivalent.size(), 40u);
    for (double s : equivalent) largest = std::max(largest, s);
  }
  std::printf("[ measured ] tied-pendulum: largest von Mises %.3e Pa over %zu frames\n", largest, sets.size());
  EXPECT_GT(largest, 0.0);
  EXPECT_LT(largest, 1e-5 * 1e10);
}

// SSNV503 in 2D, quasi-static: the shoe, 2 mm above the plate (rotated by 30°), is pressed on it by
// 300 N/mm² over 40 mm. Its contacts' files give the contact force (N), not force × pseudo-time step
// under the name impulse, and the points and gaps of the converged configuration, not of the step's
// start: at every frame a closed contact sits on the plate (gap ≈ 0, its point on the plate's surface
// n·x = 5 mm), and at the end the normal forces add up to the load, 12 000 N less the two top
// springs' 0.005 N/mm × (2 mm + the shoe's compression).
TEST(VtkWriter, QuasiStaticContactsGiveTheForcesOfTheConvergedStep) {
  const fs::path dir = fresh_directory("csim_vtk_ssnv503");
  const auto scene = load_scene(CSIM_SOURCE_DIR "/scenes/ssnv503-2d/scene.yaml", {});
  const RunReport report = run_scene(*scene, {dir.string()});
  const double angle = M_PI / 6.0;
  const Eigen::Vector3d plate_normal(-std::sin(angle), std::cos(angle), 0.0);
  const std::size_t frames = report.sample_times.size();
  ASSERT_EQ(frames, 21u);
  int closed_frames = 0;
  for (std::size_t k = 1; k < frames; ++k) {
    char name[48];  // room for any size_t, so that the compiler sees no truncation
    std::snprintf(name, sizeof name, "contacts_%06zu.vtu", k);
    const XmlElement piece = piece_of(read_vtu(dir / "paraview" / name));
    const XmlElement& data = piece.child("PointData");
    EXPECT_THROW(data.array("impulse"), std::runtime_error);
    const std::vector<double> force = data.array("force").numbers(), gap = data.array("gap").numbers(),
                              points = piece.child("Points").child("DataArray").numbers();
    ASSERT_EQ(force.size(), 3 * gap.size());
    double normal_sum = 0.0;
    for (std::size_t i = 0; i < gap.size(); ++i) {
      normal_sum += force[3 * i];
      EXPECT_GT(force[3 * i], 0.0);
      EXPECT_NEAR(gap[i], 0.0, 1e-6) << "mm, frame " << k << ", contact " << i;
      const Eigen::Vector3d x(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
      EXPECT_NEAR(plate_normal.dot(x), 5.0, 1e-6) << "mm, frame " << k << ", contact " << i;
    }
    EXPECT_NEAR(normal_sum, report.samples[k][0], 1e-9 * std::abs(report.samples[k][0]));  // the fn probe
    if (!gap.empty()) ++closed_frames;
    if (k + 1 == frames) {
      const double compression = 300.0 / 2.1e5 * 20.0;  // mm: σ/E over the shoe's height, ν = 0
      EXPECT_NEAR(normal_sum, 300.0 * 40.0 - 2.0 * 0.005 * (2.0 + compression), 0.01);
    }
  }
  EXPECT_EQ(closed_frames, 20);
}

TEST(VtkWriter, LumpedSceneWritesNoParaviewFiles) {
  const fs::path dir = fresh_directory("csim_vtk_incline");
  const auto scene = load_scene(kIncline, {"time.end=0.01", "checks.slide_at_half_time.at=0.005"});
  run_scene(*scene, {dir.string()});
  EXPECT_TRUE(fs::exists(dir / "probes.csv"));
  EXPECT_FALSE(fs::exists(dir / "paraview"));
}

TEST(VtkWriter, StaleFramesOfAnEarlierRunAreRemoved) {
  const fs::path dir = fresh_directory("csim_vtk_stale");
  fs::create_directories(dir / "paraview");
  std::ofstream(dir / "paraview" / "bar_000099.vtu") << "old";
  const auto scene = load_scene(kBar, {"time.end=2e-5"});
  run_scene(*scene, {dir.string()});
  EXPECT_FALSE(fs::exists(dir / "paraview" / "bar_000099.vtu"));
  EXPECT_TRUE(fs::exists(dir / "paraview" / "bar_000002.vtu"));
}

TEST(VtkWriter, UnfinishedSeriesLeavesNoFiles) {
  const fs::path dir = fresh_directory("csim_vtk_unfinished");
  const auto scene = load_scene(kBar, {"time.end=1e-5"});
  State state;
  state.q.setZero(scene->world.position_size);
  state.v.setZero(scene->world.velocity_size);
  {
    ParaviewSeries series(scene->world, dir.string(), VtkEncoding::binary);
    series.write_frame(scene->world, state, 0.0);
    series.wait();
    EXPECT_TRUE(fs::exists(dir / "paraview" / "bar_000000.vtu"));
  }  // destroyed without finish(): as when the run stops with an error
  EXPECT_FALSE(fs::exists(dir / "paraview"));
}

}  // namespace
}  // namespace csim
