// bodies of type elastic: a finite-element body (fem/) built from a mesh generator or a Gmsh file.
//   mesh: {generator: rectangle, size: [w, h], divisions: [nx, ny], element: quad4 | quad8}
//       | {generator: box, size: [lx, ly, lz], divisions: [nx, ny, nz]}                (hexa8)
//       | {generator: annulus, inner_radius, outer_radius, divisions: [n_around, n_radial], element}
//                                                                                (quad4 | quad8)
//       | {generator: annulus, inner_radius, outer_radius, width (m), divisions: [n_around, n_radial,
//          n_axial], element: hexa8}  (the ring extruded along z over −width/2 ≤ z ≤ width/2; its node
//          set "all" serves plane strain: fixed: {all: [z]})
//       | {file: NAME.msh}  (Gmsh MSH 4.1 ASCII, beside the scene file)
//     with an optional position (m) and angle (deg) for the generators;
//   material: {young (Pa), poisson, density (kg/m³)} (linear elasticity, small strain), or a finite-strain
//     law (total Lagrangian, fem/finite_strain.h; the body is then nonlinear):
//       {law: saint-venant-kirchhoff | neo-hookean, young, poisson, density, formulation}
//       {law: mooney-rivlin, c10, c01 (Pa), bulk (Pa), density, formulation}
//     formulation: standard | mean-dilatation | linear-dilatation (quad8 only, Q2/P1) (default for
//     mooney-rivlin, which is nearly incompressible: linear-dilatation on quad8, mean-dilatation on
//     quad4 and hexa8; standard otherwise); or the name of an entry of the scene's top-level
//     `materials` map (e.g. material: =material with a text parameter); every entry of that map is
//     checked, used or not;
//   thickness (m, plane strain, default 1);
//   mass: consistent | lumped; fixed: {SET: [x, y(, z)]}: the components held at zero on a node set
//   (or face set) of the mesh; velocity: a uniform initial velocity (m/s); angular_velocity: a rigid
//   spin added to it (plane scenes: ω rad/s about z, through the origin: v = ω ẑ × x);
//   tie: {nodes: SET, body: RIGID}: the set's nodes move with a rigid body (world.h, RigidTie).
#include "engine/bodies/fe_body.h"
#include "engine/reduced_coordinates.h"
#include "tools/scene/scene_parts.h"
#include "fem/assembly.h"
#include "fem/gmsh_reader.h"
#include "fem/mesh_generators.h"

#include <cmath>
#include <filesystem>
#include <optional>

namespace csim::scene_parts {

namespace {

int whole(const SceneNode& node, double value, const std::string& what) {
  if (value < 1 || value != std::floor(value)) node.fail(what + " must be whole numbers >= 1");
  return static_cast<int>(value);
}

ElementType element_type(const SceneNode& node, const std::string& default_type) {
  const std::string name = node.string("element", default_type);
  if (name == "quad4") return ElementType::quad4;
  if (name == "quad8") return ElementType::quad8;
  if (name == "hexa8") return ElementType::hexa8;
  node.fail_at("element", "unknown element '" + name + "' (available: quad4, quad8, hexa8)");
}

// The annulus generator: a plane ring (quad4, quad8), or with element hexa8 the ring extruded over
// its width, which then takes a third division (layers along z).
Mesh read_annulus(const SceneNode& node, const Placement& placement) {
  const ElementType type = element_type(node, "quad4");
  const double inner_radius = node.positive("inner_radius"), outer_radius = node.positive("outer_radius");
  if (type == ElementType::hexa8) {
    const Eigen::Vector3d n = node.vector("divisions", 3, 3);
    const SceneNode divisions = node.child("divisions");
    return annulus_mesh_3d(inner_radius, outer_radius, node.positive("width"), whole(divisions, n.x(), "divisions"),
                           whole(divisions, n.y(), "divisions"), whole(divisions, n.z(), "divisions"), placement);
  }
  // A plane ring is plane strain: its out-of-plane size is the body's thickness, not a mesh key.
  if (node.has("width"))
    node.fail_at("width", "only for a hexa8 annulus (a " + std::string(to_string(type)) +
                              " ring is plane: give the body a thickness instead)");
  const Eigen::Vector3d n = node.vector("divisions", 2, 2);
  const SceneNode divisions = node.child("divisions");
  return annulus_mesh(inner_radius, outer_radius, whole(divisions, n.x(), "divisions"),
                      whole(divisions, n.y(), "divisions"), type, placement);
}

// Checked before the file is opened: opening a FIFO blocks until a writer comes, /dev/zero reads
// gigabytes before the reader can say it is no mesh, and a directory reads as an empty file.
void refuse_unless_regular(const SceneNode& key, const std::filesystem::path& file) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(file, error);
  using std::filesystem::file_type;
  const file_type type = status.type();
  if (type == file_type::regular || type == file_type::not_found || type == file_type::none) return;  // read_gmsh
  const char* kind = type == file_type::directory   ? "a directory"
                     : type == file_type::fifo      ? "a FIFO (named pipe)"
                     : type == file_type::character ? "a character device"
                     : type == file_type::block     ? "a block device"
                     : type == file_type::socket    ? "a socket"
                                                    : "of an unknown kind";
  key.fail("'" + file.string() + "' is " + kind + ", not a regular file: a mesh is read from a Gmsh .msh file");
}

Mesh build_mesh(const SceneNode& node, int dimension) {
  node.allow_only({"generator", "file", "size", "divisions", "element", "inner_radius", "outer_radius", "width",
                   "position", "angle"});
  try {
    if (node.has("file")) {
      if (node.has("generator")) node.fail("give either file or generator, not both");
      const std::filesystem::path scene_folder = std::filesystem::path(node.document().file).parent_path();
      const std::filesystem::path file = scene_folder / node.string("file");
      refuse_unless_regular(node.child("file"), file);
      return read_gmsh(file.string());
    }
    Placement placement;
    if (node.has("position")) placement.offset = node.vector("position", dimension, dimension);
    placement.angle = node.number("angle", 0.0) * M_PI / 180.0;
    const std::string generator = node.string("generator");
    if (generator == "rectangle") {
      const Eigen::Vector3d size = node.vector("size", 2, 2), divisions = node.vector("divisions", 2, 2);
      return rectangle_mesh(size.x(), size.y(), whole(node.child("divisions"), divisions.x(), "divisions"),
                            whole(node.child("divisions"), divisions.y(), "divisions"), element_type(node, "quad4"),
                            placement);
    }
    if (generator == "box") {
      const Eigen::Vector3d size = node.vector("size", 3, 3), n = node.vector("divisions", 3, 3);
      const SceneNode divisions = node.child("divisions");
      return box_mesh(size.x(), size.y(), size.z(), whole(divisions, n.x(), "divisions"),
                      whole(divisions, n.y(), "divisions"), whole(divisions, n.z(), "divisions"), placement);
    }
    if (generator == "annulus") return read_annulus(node, placement);
    node.fail_at("generator", "unknown mesh generator '" + generator + "' (available: rectangle, box, annulus)");
  } catch (const FemError& e) {
    node.fail(e.what());
  }
}

// A degenerate or inverted element is named at the mesh key: FeBody finds it too, but its errors are
// reported at the material key.
Mesh read_mesh(const SceneNode& node, int dimension) {
  Mesh mesh = build_mesh(node, dimension);
  try {
    check_mesh(mesh);
  } catch (const FemError& e) {
    node.fail(e.what());
  }
  return mesh;
}

// The body's material node, or the top-level `materials` entry it names.
SceneNode material_definition(const SceneNode& body) {
  const SceneNode material = body.child("material");
  if (!material.is_scalar()) return material;
  const std::string name = material.as_string();
  const SceneNode root(body.document().root, "", &body.document(), 1);
  if (!root.has("materials") || !root.child("materials").has(name))
    material.fail("no entry '" + name + "' in the scene's top-level materials");
  return root.child("materials").child(name);
}

FiniteStrainFormulation formulation_named(const SceneNode& node, const std::string& name) {
  if (name == "standard") return FiniteStrainFormulation::standard;
  if (name == "mean-dilatation") return FiniteStrainFormulation::mean_dilatation;
  if (name == "linear-dilatation") return FiniteStrainFormulation::linear_dilatation;
  node.fail_at("formulation", "expected standard, mean-dilatation or linear-dilatation");
}

// Without an element (an entry of `materials` that no body uses), the formulation's default and its fit to
// the element are left to the body that picks the entry; an explicit formulation's name is checked now.
FiniteStrainLaw read_finite_strain_law(const SceneNode& node, const std::string& law,
                                       std::optional<ElementType> element) {
  FiniteStrainLaw result;
  try {
    if (law == "saint-venant-kirchhoff" || law == "neo-hookean") {
      node.allow_only({"law", "young", "poisson", "density", "formulation"});
      const double young = node.number("young"), poisson = node.number("poisson", 0.0),
                   density = node.number("density");
      result.material = law == "neo-hookean" ? neo_hookean(young, poisson, density)
                                             : saint_venant_kirchhoff(young, poisson, density);
    } else if (law == "mooney-rivlin") {
      node.allow_only({"law", "c10", "c01", "bulk", "density", "formulation"});
      result.material = mooney_rivlin(node.number("c10"), node.number("c01", 0.0), node.number("bulk"),
                                      node.number("density"));
      check_hyperelastic(result.material);
    } else {
      node.fail_at("law", "unknown material law '" + law +
                              "' (available: linear, saint-venant-kirchhoff, neo-hookean, mooney-rivlin)");
    }
  } catch (const FemError& e) {
    node.fail(e.what());
  }
  if (!element) {
    if (node.has("formulation")) formulation_named(node, node.string("formulation"));
    return result;
  }
  const char* mixed = *element == ElementType::quad8 ? "linear-dilatation" : "mean-dilatation";
  const std::string formulation = node.string("formulation", law == "mooney-rivlin" ? mixed : "standard");
  result.formulation = formulation_named(node, formulation);
  try {
    check_formulation(*element, result.formulation);
  } catch (const FemError& e) {
    node.fail_at("formulation", e.what());
  }
  return result;
}

// A body's material: linear elasticity, or a finite-strain law.
struct BodyMaterial {
  ElasticMaterial linear;
  std::optional<FiniteStrainLaw> finite_strain;
};

BodyMaterial read_material(const SceneNode& node, std::optional<ElementType> element) {
  node.expect_map();
  BodyMaterial material;
  const std::string law = node.string("law", "linear");
  if (law != "linear") {
    material.finite_strain = read_finite_strain_law(node, law, element);
    return material;
  }
  node.allow_only({"law", "young", "poisson", "density"});
  material.linear.young = node.number("young");
  material.linear.poisson = node.number("poisson", 0.0);
  material.linear.density = node.number("density");
  try {
    check_material(material.linear);
  } catch (const FemError& e) {
    node.fail(e.what());
  }
  return material;
}

// The nodes of a node set, or of a face set, of the mesh; nullopt when it has neither.
std::optional<std::vector<int>> nodes_of_set(const Mesh& mesh, const std::string& set) {
  if (mesh.node_sets.count(set)) return mesh.node_sets.at(set);
  if (mesh.face_sets.count(set)) return nodes_of(mesh.face_sets.at(set));
  return std::nullopt;
}

}  // namespace

// Every entry of the top-level materials map is read, used or not: a mistake in an entry that the
// parameters do not pick today would otherwise surface only on the day they do.
void read_materials(const SceneNode& root) {
  if (!root.has("materials")) return;
  for (const auto& entry : root.child("materials").entries()) read_material(entry.second, std::nullopt);
}

// The ties of the elastic bodies, once every body exists (the rigid body may come later in the file).
void read_ties(const SceneNode& root, World& world) {
  for (const auto& [name, node] : root.child("bodies").entries()) {
    if (!node.has("tie")) continue;
    const SceneNode tie_node = node.child("tie");
    tie_node.allow_only({"nodes", "body"});
    RigidTie tie;
    tie.name = name;
    tie.elastic_body = world.body_index(name);
    tie.rigid_body = body_named(tie_node, "body", world);
    const FeBody* fe = world.bodies[tie.elastic_body].body->finite_elements();  // read_ties: only elastic bodies
    const Body& rigid = *world.bodies[tie.rigid_body].body;
    if (rigid.elastic() || rigid.velocity_size() != 3 * (world.dimension - 1))
      tie_node.fail_at("body", "a tie joins an elastic body to a rigid body");
    const std::string set = tie_node.string("nodes");
    const auto nodes = nodes_of_set(fe->mesh(), set);
    if (!nodes) tie_node.fail_at("nodes", "the mesh has no node or face set '" + set + "'");
    tie.nodes = *nodes;
    world.ties.push_back(tie);
    // The whole body rides in its hub's frame (reduced_coordinates.h): a fixed component only where
    // the frame cannot move it (plane strain across a ring on an axle held in its plane).
    if (fe->velocity_size() != fe->dofs_per_node() * static_cast<int>(fe->mesh().nodes.size())) {
      try {
        ReducedCoordinates check(world, 0.0);
      } catch (const std::invalid_argument& e) {
        node.fail_at("fixed", std::string("a tied body rides on its hub: ") + e.what());
      }
    }
  }
}

void read_elastic_body(const std::string& name, const SceneNode& node, World& world) {
  node.allow_only({"type", "mesh", "material", "thickness", "mass", "fixed", "velocity", "angular_velocity", "damping",
                   "tie", "group"});
  Mesh mesh = read_mesh(node.child("mesh"), world.dimension);
  if (mesh.dimension() != world.dimension)
    node.fail_at("mesh", "a " + std::string(to_string(mesh.element_type)) + " mesh in a " +
                             std::to_string(world.dimension) + "D scene");
  const BodyMaterial material = read_material(material_definition(node), mesh.element_type);
  const double thickness = node.has("thickness") ? node.positive("thickness") : 1.0;
  const std::string mass = node.string("mass", "consistent");
  if (mass != "consistent" && mass != "lumped") node.fail_at("mass", "expected consistent or lumped");

  // Rayleigh damping {alpha: 1/s, beta: s}: C = alpha M + beta K.
  double alpha = 0.0, beta = 0.0;
  if (node.has("damping")) {
    const SceneNode damping = node.child("damping");
    damping.allow_only({"alpha", "beta"});
    alpha = damping.non_negative("alpha", 0.0);
    beta = damping.non_negative("beta", 0.0);
    // β K_0 would resist rigid rotations (K_0 is the tangent at the reference configuration).
    if (beta > 0.0 && material.finite_strain)
      damping.fail_at("beta", "stiffness-proportional damping is not defined for a finite-strain law (use alpha)");
  }

  std::vector<std::pair<int, int>> fixed;
  if (node.has("fixed")) {
    for (const auto& [set, components] : node.child("fixed").entries()) {
      const auto nodes = nodes_of_set(mesh, set);
      if (!nodes) components.fail("the mesh has no node or face set '" + set + "'");
      for (const SceneNode& component : components.items()) {
        const std::string axis = component.as_string();
        const int c = axis == "x" ? 0 : axis == "y" ? 1 : axis == "z" && world.dimension == 3 ? 2 : -1;
        if (c < 0) component.fail("expected x, y" + std::string(world.dimension == 3 ? " or z" : ""));
        for (int n : *nodes) fixed.emplace_back(n, c);
      }
    }
  }

  BodyInstance b;
  b.name = name;
  std::unique_ptr<FeBody> fe_body;
  try {
    if (material.finite_strain)
      fe_body = std::make_unique<FeBody>(std::move(mesh), *material.finite_strain, thickness, mass == "lumped", fixed,
                                         alpha, beta);
    else
      fe_body =
          std::make_unique<FeBody>(std::move(mesh), material.linear, thickness, mass == "lumped", fixed, alpha, beta);
  } catch (const FemError& e) {
    node.child("material").fail(e.what());
  }
  const FeBody& body = *fe_body;
  b.body = std::move(fe_body);
  const int n = body.velocity_size();
  b.reference_position.setZero(n);
  b.initial_position.setZero(n);
  b.initial_velocity.setZero(n);
  if (node.has("velocity") || node.has("angular_velocity")) {
    const Eigen::Vector3d velocity =
        node.has("velocity") ? node.vector("velocity", world.dimension, world.dimension) : Eigen::Vector3d::Zero();
    double spin = 0.0;
    if (node.has("angular_velocity")) {
      if (world.dimension != 2) node.fail_at("angular_velocity", "only in plane scenes (a rate about z) so far");
      spin = node.number("angular_velocity");
    }
    for (int i = 0; i < static_cast<int>(body.mesh().nodes.size()); ++i) {
      const Eigen::Vector3d& x = body.mesh().nodes[i];
      const Eigen::Vector3d v = velocity + spin * Eigen::Vector3d(-x.y(), x.x(), 0.0);
      for (int c = 0; c < body.dofs_per_node(); ++c)
        if (body.free_index(i, c) >= 0) b.initial_velocity(body.free_index(i, c)) = v(c);
    }
  }
  world.bodies.push_back(std::move(b));
}

}  // namespace csim::scene_parts
