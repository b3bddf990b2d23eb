#include "tools/output/vtk_writer.h"

#include "engine/bodies/fe_body.h"
#include "tools/output/atomic_file.h"

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

// Shortest text that reads back as the same double: files stay small and a value read from them is
// bit-for-bit the simulated one.
void put_number(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void put_number(std::string& out, long value) { out += std::to_string(value); }

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

// A DataArray of `components` components; `values` is written one tuple per line. Component names
// show in ParaView's array selector instead of 0, 1, 2.
template <typename T>
void put_array(std::string& out, const char* type, const std::string& name, int components,
               const std::vector<T>& values, const std::vector<std::string>& component_names = {}) {
  out += "        <DataArray type=\"" + std::string(type) + "\"";
  if (!name.empty()) out += " Name=\"" + name + "\"";
  out += " NumberOfComponents=\"" + std::to_string(components) + "\"";
  for (std::size_t c = 0; c < component_names.size(); ++c)
    out += " ComponentName" + std::to_string(c) + "=\"" + component_names[c] + "\"";
  out += " format=\"ascii\">\n";
  for (std::size_t i = 0; i < values.size(); ++i) {
    out += (i % components == 0) ? "          " : " ";
    put_number(out, values[i]);
    if ((i + 1) % components == 0) out += '\n';
  }
  out += "        </DataArray>\n";
}

// Node-major dofs (d per node) as 3-component tuples, z = 0 for plane meshes.
std::vector<double> as_vectors(const Eigen::VectorXd& dofs, int nodes, int d) {
  std::vector<double> out(3 * static_cast<std::size_t>(nodes), 0.0);
  for (int i = 0; i < nodes; ++i)
    for (int c = 0; c < d; ++c) out[3 * i + c] = dofs(d * i + c);
  return out;
}

// An XML comment line: "--" may not occur inside one, nor '-' at its end.
std::string comment_line(const std::string& text) {
  std::string body;
  for (char c : text) body += (c == '-' && !body.empty() && body.back() == '-') ? std::string(" -") : std::string(1, c);
  return "<!-- " + body + " -->\n";
}

// The file's head and tail; the time also goes into FieldData (TimeValue), which ParaView reads when a
// single .vtu is opened without its .pvd. `comments`: lines that say what the arrays are, before the root.
std::string grid_head(double t, std::size_t points, std::size_t cells, const std::vector<std::string>& comments = {}) {
  std::string out = "<?xml version=\"1.0\"?>\n";
  for (const std::string& c : comments) out += comment_line(c);
  out +=
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <UnstructuredGrid>\n"
      "    <FieldData>\n"
      "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">";
  put_number(out, t);
  out += "</DataArray>\n    </FieldData>\n";
  out += "    <Piece NumberOfPoints=\"" + std::to_string(points) + "\" NumberOfCells=\"" + std::to_string(cells) +
         "\">\n";
  return out;
}

const char* const kGridTail = "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";

void put_cells(std::string& out, const std::vector<long>& connectivity, const std::vector<long>& offsets,
               int type) {
  out += "      <Cells>\n";
  put_array(out, "Int64", "connectivity", 1, connectivity);
  put_array(out, "Int64", "offsets", 1, offsets);
  put_array(out, "UInt8", "types", 1, std::vector<long>(offsets.size(), type));
  out += "      </Cells>\n";
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

std::string fe_body_vtu(const Mesh& mesh, const Eigen::VectorXd& displacement, const Eigen::VectorXd& velocity,
                        const ElementFields& fields, double t) {
  const int nodes = static_cast<int>(mesh.nodes.size()), d = mesh.dofs_per_node();
  const bool strain = !fields.strain.empty();
  std::vector<std::string> comments{"stress: " + fields.stress_description,
                                    "von_mises, pressure (-trace/3, compression positive): from stress"};
  if (strain) comments.push_back("green_lagrange_strain: " + fields.strain_description);
  std::string out = grid_head(t, mesh.nodes.size(), mesh.elements.size(), comments);
  out += "      <PointData Vectors=\"displacement\">\n";
  put_array(out, "Float64", "displacement", 3, as_vectors(displacement, nodes, d));
  put_array(out, "Float64", "velocity", 3, as_vectors(velocity, nodes, d));
  out += "      </PointData>\n";
  // Six components in VTK's symmetric-tensor order (XX, YY, ZZ, XY, YZ, XZ), which is fem's: ParaView
  // computes eigenvalues and invariants of it directly.
  const std::vector<std::string> components{"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
  std::vector<double> stress, equivalent, pressure, strains;
  for (const Stress& s : fields.stress) {
    stress.insert(stress.end(), s.data(), s.data() + 6);
    equivalent.push_back(von_mises(s));
    pressure.push_back(mean_pressure(s));
  }
  for (const Stress& e : fields.strain) strains.insert(strains.end(), e.data(), e.data() + 6);
  out += "      <CellData Tensors=\"stress\" Scalars=\"von_mises\">\n";
  put_array(out, "Float64", "stress", 6, stress, components);
  put_array(out, "Float64", "von_mises", 1, equivalent);
  put_array(out, "Float64", "pressure", 1, pressure);
  if (strain) put_array(out, "Float64", "green_lagrange_strain", 6, strains, components);
  out += "      </CellData>\n";
  std::vector<double> points;
  for (const Eigen::Vector3d& x : mesh.nodes) points.insert(points.end(), {x(0), x(1), x(2)});
  out += "      <Points>\n";
  put_array(out, "Float64", "", 3, points);
  out += "      </Points>\n";
  std::vector<long> connectivity, offsets;
  for (const std::vector<int>& element : mesh.elements) {
    connectivity.insert(connectivity.end(), element.begin(), element.end());
    offsets.push_back(static_cast<long>(connectivity.size()));
  }
  put_cells(out, connectivity, offsets, vtk_cell_type(mesh.element_type));
  return out + kGridTail;
}

std::string contacts_vtu(const std::vector<ActiveContact>& contacts, double t) {
  std::vector<double> points, impulse, normal, gap;
  std::vector<long> status, connectivity, offsets;
  for (const ActiveContact& c : contacts) {
    const Eigen::Vector3d x = 0.5 * (c.point.point_a + c.point.point_b);
    points.insert(points.end(), {x(0), x(1), x(2)});
    impulse.insert(impulse.end(), {c.impulse(0), c.impulse(1), c.impulse(2)});
    normal.insert(normal.end(), {c.point.normal(0), c.point.normal(1), c.point.normal(2)});
    gap.push_back(c.point.gap);
    status.push_back(static_cast<long>(c.status));  // open 0, stick 1, slip 2: ContactStatus's order
    connectivity.push_back(static_cast<long>(offsets.size()));
    offsets.push_back(static_cast<long>(offsets.size()) + 1);
  }
  std::string out = grid_head(t, contacts.size(), contacts.size());
  out += "      <PointData Scalars=\"status\" Vectors=\"normal\">\n";
  put_array(out, "Int32", "status", 1, status);
  put_array(out, "Float64", "impulse", 3, impulse, {"normal", "t1", "t2"});
  put_array(out, "Float64", "normal", 3, normal);
  put_array(out, "Float64", "gap", 1, gap);
  out += "      </PointData>\n      <Points>\n";
  put_array(out, "Float64", "", 3, points);
  out += "      </Points>\n";
  put_cells(out, connectivity, offsets, 1);  // VTK_VERTEX
  return out + kGridTail;
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

ParaviewSeries::ParaviewSeries(const World& world, const std::string& output_directory)
    : directory_((std::filesystem::path(output_directory) / "paraview").string()) {
  // The caller has checked the names (check_outputs); this is what a series cannot be written without.
  if (const auto problem = paraview_name_problem(world, 0))
    throw std::runtime_error(directory_ + ": body '" + problem->body + "': " + problem->message);
  for (std::size_t i = 0; i < world.bodies.size(); ++i)
    if (world.bodies[i].body->finite_elements())
      series_.push_back({static_cast<int>(i), file_stem(world.bodies[i].name), {}});
  series_.push_back({-1, "contacts", {}});
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
      write(s, contacts_vtu(state.contacts, t));
      continue;
    }
    const BodyInstance& b = world.bodies[s.body];
    const FeBody& body = *b.body->finite_elements();  // a series is only opened for a finite-element body
    const Eigen::VectorXd u = body.full_displacement(state.q.segment(b.position_offset, body.position_size()));
    // v holds the same free dofs as q, so the same expansion gives the velocity of every dof.
    const Eigen::VectorXd v = body.full_displacement(state.v.segment(b.velocity_offset, body.velocity_size()));
    write(s, fe_body_vtu(body.mesh(), u, v, element_fields(body, u), t));
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
