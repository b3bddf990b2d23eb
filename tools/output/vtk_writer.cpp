#include "tools/output/vtk_writer.h"

#include "engine/bodies/fe_body.h"
#include "tools/output/atomic_file.h"
#include "tools/output/vtk_data_array.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <system_error>

namespace csim {

namespace {

// Shortest text that reads back as the same double (the time in the head and the .pvd).
void put_number(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

std::string escaped(const std::string& text) {  // for an attribute value in double quotes
  std::string out;
  for (char c : text) {
    if (c == '&') out += "&amp;";
    else if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

// Node-major dofs (d per node) as 3-component tuples, z = 0 for plane meshes.
std::vector<double> as_vectors(const Eigen::VectorXd& dofs, std::size_t nodes, int d) {
  std::vector<double> out(3 * nodes, 0.0);
  for (std::size_t i = 0; i < nodes; ++i)
    for (int c = 0; c < d; ++c) out[3 * i + c] = dofs(d * i + c);
  return out;
}

// An XML comment line: "--" may not occur inside one, nor '-' at its end.
std::string comment_line(const std::string& text) {
  std::string body;
  for (char c : text) body += (c == '-' && !body.empty() && body.back() == '-') ? std::string(" -") : std::string(1, c);
  return "<!-- " + body + " -->\n";
}

// The file's head up to <Piece>; the time also goes into FieldData (TimeValue, always as text), which
// ParaView reads when a single .vtu is opened without its .pvd. `comments`: lines that say what the
// arrays are, before the root.
void open_grid(VtkFileText& file, double t, std::size_t points, std::size_t cells,
               const std::vector<std::string>& comments = {}) {
  std::string prolog;
  for (const std::string& c : comments) prolog += comment_line(c);
  file.open("UnstructuredGrid", prolog);
  std::string& out = file.xml();
  out +=
      "  <UnstructuredGrid>\n"
      "    <FieldData>\n"
      "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">";
  put_number(out, t);
  out += "</DataArray>\n    </FieldData>\n";
  out += "    <Piece NumberOfPoints=\"" + std::to_string(points) + "\" NumberOfCells=\"" + std::to_string(cells) +
         "\">\n";
}

void close_grid(VtkFileText& file) { file.xml() += "    </Piece>\n  </UnstructuredGrid>\n"; }

void put_points_and_cells(VtkFileText& file, const EncodedArray& points, const EncodedArray& connectivity,
                          const EncodedArray& offsets, const EncodedArray& types) {
  file.xml() += "      <Points>\n";
  file.array(points);
  file.xml() += "      </Points>\n      <Cells>\n";
  file.array(connectivity);
  file.array(offsets);
  file.array(types);
  file.xml() += "      </Cells>\n";
}

// A body name as a file-name prefix: characters outside [A-Za-z0-9_.-] become '_'.
std::string file_stem(const std::string& name) {
  std::string stem = name.empty() ? "_" : name;
  for (char& c : stem)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-')) c = '_';
  return stem;
}

std::string frame_name(const std::string& stem, std::size_t frame) {
  char number[32];
  std::snprintf(number, sizeof number, "_%06zu.vtu", frame);
  return stem + number;
}

// The longest name a folder entry may have on Linux (NAME_MAX); a longer one fails at open().
constexpr std::size_t kNameMax = 255;
const char* const kTemporarySuffix = ".tmp";  // write_file_atomically's

}  // namespace

int vtk_cell_type(ElementType type) {
  switch (type) {
    case ElementType::quad4: return 9;
    case ElementType::quad8: return 23;
    case ElementType::hexa8: return 12;
  }
  throw std::logic_error("vtk_cell_type: unknown element type");
}

double mean_pressure(const Stress& s) { return -(s(0) + s(1) + s(2)) / 3.0; }

double von_mises(const Stress& s) {
  const double normal = (s(0) - s(1)) * (s(0) - s(1)) + (s(1) - s(2)) * (s(1) - s(2)) + (s(2) - s(0)) * (s(2) - s(0));
  const double shear = s(3) * s(3) + s(4) * s(4) + s(5) * s(5);
  return std::sqrt(0.5 * normal + 3.0 * shear);
}

EncodedMesh encode_mesh(const Mesh& mesh, VtkEncoding encoding) {
  EncodedMesh out;
  out.encoding = encoding;
  out.points = mesh.nodes.size();
  out.cells = mesh.elements.size();
  out.dofs_per_node = mesh.dofs_per_node();
  std::vector<double> points;
  points.reserve(3 * out.points);
  for (const Eigen::Vector3d& x : mesh.nodes) points.insert(points.end(), {x(0), x(1), x(2)});
  std::vector<std::int64_t> connectivity, offsets;
  for (const std::vector<int>& element : mesh.elements) {
    connectivity.insert(connectivity.end(), element.begin(), element.end());
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  }
  out.coordinates = encode_array(encoding, "Float64", "", 3, points);
  out.connectivity = encode_array(encoding, "Int64", "connectivity", 1, connectivity);
  out.offsets = encode_array(encoding, "Int64", "offsets", 1, offsets);
  out.types = encode_array(encoding, "UInt8", "types", 1,
                           std::vector<std::int64_t>(offsets.size(), vtk_cell_type(mesh.element_type)));
  return out;
}

std::string fe_body_vtu(const EncodedMesh& mesh, const Eigen::VectorXd& displacement, const Eigen::VectorXd& velocity,
                        const ElementFields& fields, double t) {
  const VtkEncoding encoding = mesh.encoding;
  const bool strain = !fields.strain.empty();
  std::vector<std::string> comments{"stress: " + fields.stress_description,
                                    "von_mises, pressure (-trace/3, compression positive): from stress"};
  if (strain) comments.push_back("green_lagrange_strain: " + fields.strain_description);
  VtkFileText file(encoding);
  open_grid(file, t, mesh.points, mesh.cells, comments);
  file.xml() += "      <PointData Vectors=\"displacement\">\n";
  file.array(encode_array(encoding, "Float64", "displacement", 3, as_vectors(displacement, mesh.points, mesh.dofs_per_node)));
  file.array(encode_array(encoding, "Float64", "velocity", 3, as_vectors(velocity, mesh.points, mesh.dofs_per_node)));
  file.xml() += "      </PointData>\n";
  // Six components in VTK's symmetric-tensor order (XX, YY, ZZ, XY, YZ, XZ), which is fem's: ParaView
  // computes eigenvalues and invariants of it directly.
  const std::vector<std::string> components{"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
  std::vector<double> stress, equivalent, pressure, strains;
  stress.reserve(6 * fields.stress.size());
  for (const Stress& s : fields.stress) {
    stress.insert(stress.end(), s.data(), s.data() + 6);
    equivalent.push_back(von_mises(s));
    pressure.push_back(mean_pressure(s));
  }
  for (const Stress& e : fields.strain) strains.insert(strains.end(), e.data(), e.data() + 6);
  file.xml() += "      <CellData Tensors=\"stress\" Scalars=\"von_mises\">\n";
  file.array(encode_array(encoding, "Float64", "stress", 6, stress, components));
  file.array(encode_array(encoding, "Float64", "von_mises", 1, equivalent));
  file.array(encode_array(encoding, "Float64", "pressure", 1, pressure));
  if (strain) file.array(encode_array(encoding, "Float64", "green_lagrange_strain", 6, strains, components));
  file.xml() += "      </CellData>\n";
  put_points_and_cells(file, mesh.coordinates, mesh.connectivity, mesh.offsets, mesh.types);
  close_grid(file);
  return file.finish();
}

std::string fe_body_vtu(const Mesh& mesh, const Eigen::VectorXd& displacement, const Eigen::VectorXd& velocity,
                        const ElementFields& fields, double t, VtkEncoding encoding) {
  return fe_body_vtu(encode_mesh(mesh, encoding), displacement, velocity, fields, t);
}

std::string contacts_vtu(const std::vector<ActiveContact>& contacts, double t, VtkEncoding encoding) {
  std::vector<double> points, impulse, normal, gap;
  std::vector<std::int64_t> status, connectivity, offsets;
  for (const ActiveContact& c : contacts) {
    const Eigen::Vector3d x = 0.5 * (c.point.point_a + c.point.point_b);
    points.insert(points.end(), {x(0), x(1), x(2)});
    impulse.insert(impulse.end(), {c.impulse(0), c.impulse(1), c.impulse(2)});
    normal.insert(normal.end(), {c.point.normal(0), c.point.normal(1), c.point.normal(2)});
    gap.push_back(c.point.gap);
    status.push_back(static_cast<std::int64_t>(c.status));  // open 0, stick 1, slip 2: ContactStatus's order
    connectivity.push_back(static_cast<std::int64_t>(offsets.size()));
    offsets.push_back(static_cast<std::int64_t>(offsets.size()) + 1);
  }
  VtkFileText file(encoding);
  open_grid(file, t, contacts.size(), contacts.size());
  file.xml() += "      <PointData Scalars=\"status\" Vectors=\"normal\">\n";
  file.array(encode_array(encoding, "Int32", "status", 1, status));
  file.array(encode_array(encoding, "Float64", "impulse", 3, impulse, {"normal", "t1", "t2"}));
  file.array(encode_array(encoding, "Float64", "normal", 3, normal));
  file.array(encode_array(encoding, "Float64", "gap", 1, gap));
  file.xml() += "      </PointData>\n";
  const std::vector<std::int64_t> types(contacts.size(), 1);  // VTK_VERTEX
  put_points_and_cells(file, encode_array(encoding, "Float64", "", 3, points),
                       encode_array(encoding, "Int64", "connectivity", 1, connectivity),
                       encode_array(encoding, "Int64", "offsets", 1, offsets),
                       encode_array(encoding, "UInt8", "types", 1, types));
  close_grid(file);
  return file.finish();
}

std::string pvd_collection(const std::vector<CollectionEntry>& entries) {
  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  for (const CollectionEntry& e : entries) {
    out += "    <DataSet timestep=\"";
    put_number(out, e.time);
    out += "\" group=\"\" part=\"0\" file=\"" + escaped(e.file) + "\"/>\n";
  }
  return out + "  </Collection>\n</VTKFile>\n";
}

bool has_elastic_bodies(const World& world) {
  for (const BodyInstance& b : world.bodies)
    if (b.body->finite_elements()) return true;
  return false;
}

void remove_paraview_outputs(const std::string& output_directory) {
  const std::filesystem::path folder = std::filesystem::path(output_directory) / "paraview";
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error)) return;
  std::vector<std::filesystem::path> ours;  // listed first: removing while iterating is unspecified
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    const std::string extension = entry.path().extension().string();
    if (extension == ".vtu" || extension == ".pvd" || extension == ".tmp") ours.push_back(entry.path());
  }
  for (const auto& path : ours) std::filesystem::remove(path, error);
  std::filesystem::remove(folder, error);  // only succeeds when empty: files of the user's stay
}

std::optional<ParaviewNameProblem> paraview_name_problem(const World& world, std::size_t frames) {
  std::map<std::string, std::string> owners{{"contacts", "the contacts' series"}};  // stem -> whose
  for (const BodyInstance& b : world.bodies) {
    if (!b.body->finite_elements()) continue;
    const std::string stem = file_stem(b.name);
    const auto [owner, added] = owners.emplace(stem, "body '" + b.name + "'");
    if (!added)
      return ParaviewNameProblem{b.name, "its ParaView files would be named like those of " + owner->second + " (" +
                                             stem + "_*.vtu): rename one of them"};
    const std::string longest = frame_name(stem, frames > 0 ? frames - 1 : 0) + kTemporarySuffix;
    if (longest.size() > kNameMax)
      return ParaviewNameProblem{b.name, "the name is too long for its ParaView files (" + longest.substr(0, 12) +
                                             "..." + longest.substr(longest.size() - 19) + ": " +
                                             std::to_string(longest.size()) + " bytes, at most " +
                                             std::to_string(kNameMax) + "): shorten it"};
  }
  return std::nullopt;
}

ParaviewSeries::ParaviewSeries(const World& world, const std::string& output_directory, VtkEncoding encoding)
    : directory_((std::filesystem::path(output_directory) / "paraview").string()), encoding_(encoding) {
  // The caller has checked the names (check_outputs); this is what a series cannot be written without.
  if (const auto problem = paraview_name_problem(world, 0))
    throw std::runtime_error(directory_ + ": body '" + problem->body + "': " + problem->message);
  for (std::size_t i = 0; i < world.bodies.size(); ++i)
    if (world.bodies[i].body->finite_elements())
      series_.push_back({static_cast<int>(i), file_stem(world.bodies[i].name),
                         encode_mesh(world.bodies[i].body->finite_elements()->mesh(), encoding), {}});
  series_.push_back({-1, "contacts", {}, {}});
  std::error_code error;
  std::filesystem::create_directories(directory_, error);
  if (error) throw std::runtime_error(directory_ + ": cannot create the folder (" + error.message() + ")");
}

ParaviewSeries::~ParaviewSeries() {
  if (finished_) return;
  std::error_code ignored;  // a destructor must not throw; what cannot be removed stays
  const std::filesystem::path folder(directory_);
  for (const Series& s : series_) {
    for (const std::string& file : s.written) std::filesystem::remove(folder / file, ignored);
    std::filesystem::remove(folder / (s.stem + ".pvd"), ignored);  // finish() may have written some
  }
  std::filesystem::remove(directory_, ignored);
}

void ParaviewSeries::write(Series& series, const std::string& text) {
  const std::string file = frame_name(series.stem, times_.size());
  write_file_atomically((std::filesystem::path(directory_) / file).string(), text);
  series.written.push_back(file);
}

void ParaviewSeries::write_frame(const World& world, const State& state, double t) {
  for (Series& s : series_) {
    if (s.body < 0) {
      write(s, contacts_vtu(state.contacts, t, encoding_));
      continue;
    }
    const BodyInstance& b = world.bodies[s.body];
    const FeBody& body = *b.body->finite_elements();  // a series is only opened for a finite-element body
    const Eigen::VectorXd u = body.full_displacement(state.q.segment(b.position_offset, body.position_size()));
    // v holds the same free dofs as q, so the same expansion gives the velocity of every dof.
    const Eigen::VectorXd v = body.full_displacement(state.v.segment(b.velocity_offset, body.velocity_size()));
    write(s, fe_body_vtu(*s.mesh, u, v, element_fields(body, u), t));
  }
  times_.push_back(t);
}

void ParaviewSeries::finish() {
  for (const Series& s : series_) {
    std::vector<CollectionEntry> entries;
    for (std::size_t k = 0; k < s.written.size(); ++k) entries.push_back({times_[k], s.written[k]});
    write_file_atomically((std::filesystem::path(directory_) / (s.stem + ".pvd")).string(), pvd_collection(entries));
  }
  finished_ = true;
}

}  // namespace csim
