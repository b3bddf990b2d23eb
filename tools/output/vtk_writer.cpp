#include "tools/output/vtk_writer.h"

#include "tools/output/vtk_data_array.h"

#include <cmath>
#include <stdexcept>

namespace csim {

namespace {

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
  file.open_dataset("UnstructuredGrid", prolog, t);
  file.xml() += "    <Piece NumberOfPoints=\"" + std::to_string(points) + "\" NumberOfCells=\"" + std::to_string(cells) +
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

void fe_body_file(VtkFileText& file, const EncodedMesh& mesh, const Eigen::VectorXd& displacement,
                  const Eigen::VectorXd& velocity, const ElementFields& fields, double t) {
  const VtkEncoding encoding = mesh.encoding;
  const bool strain = !fields.strain.empty();
  std::vector<std::string> comments{"stress: " + fields.stress_description,
                                    "von_mises, pressure (-trace/3, compression positive): from stress"};
  if (strain) comments.push_back("green_lagrange_strain: " + fields.strain_description);
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
}

std::string fe_body_vtu(const Mesh& mesh, const Eigen::VectorXd& displacement, const Eigen::VectorXd& velocity,
                        const ElementFields& fields, double t, VtkEncoding encoding) {
  const EncodedMesh encoded = encode_mesh(mesh, encoding);
  VtkFileText file(encoding);
  fe_body_file(file, encoded, displacement, velocity, fields, t);
  return file.finish();
}

std::string contacts_vtu(const std::vector<ActiveContact>& contacts, double t, VtkEncoding encoding,
                         const ContactAction& action) {
  std::vector<double> points, impulse, normal, gap;
  const double scale = action.force ? 1.0 / action.step : 1.0;  // impulse → force
  std::vector<std::int64_t> status, connectivity, offsets;
  for (const ActiveContact& c : contacts) {
    const Eigen::Vector3d x = 0.5 * (c.point.point_a + c.point.point_b);
    points.insert(points.end(), {x(0), x(1), x(2)});
    impulse.insert(impulse.end(), {scale * c.impulse(0), scale * c.impulse(1), scale * c.impulse(2)});
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
  file.array(encode_array(encoding, "Float64", action.force ? "force" : "impulse", 3, impulse, {"normal", "t1", "t2"}));
  file.array(encode_array(encoding, "Float64", "normal", 3, normal));
  file.array(encode_array(encoding, "Float64", "gap", 1, gap));
  file.xml() += "      </PointData>\n";
  // Named: the file refers to their data until finish().
  const EncodedArray point_array = encode_array(encoding, "Float64", "", 3, points),
                     connectivity_array = encode_array(encoding, "Int64", "connectivity", 1, connectivity),
                     offset_array = encode_array(encoding, "Int64", "offsets", 1, offsets),
                     type_array = encode_array(encoding, "UInt8", "types", 1,
                                               std::vector<std::int64_t>(contacts.size(), 1));  // VTK_VERTEX
  put_points_and_cells(file, point_array, connectivity_array, offset_array, type_array);
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

}  // namespace csim
