#include "tools/output/body_shapes.h"

#include "engine/bodies/fe_body.h"
#include "tools/output/shape_outlines.h"

#include <algorithm>
#include <cstdint>
#include <variant>

namespace csim {

namespace {

// A vtkStringArray as VTK's XML writer stores it in ASCII: each string's bytes as numbers, each string
// ended by a 0 (always as text, as the TimeValue beside it).
std::string string_array(const std::string& name, const std::vector<std::string>& strings) {
  std::string out = "      <Array type=\"String\" Name=\"" + name + "\" NumberOfTuples=\"" +
                    std::to_string(strings.size()) + "\" format=\"ascii\">\n        ";
  for (const std::string& s : strings) {
    for (const char c : s) out += std::to_string(static_cast<unsigned char>(c)) + ' ';
    out += "0 ";
  }
  return out + "\n      </Array>\n";
}

// J(q) v of a material point (m/s): the velocity of the point `local` (body frame, m). On the run's
// thread only: a rigid body caches its rotation.
Eigen::Vector3d point_velocity(const Body& body, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                               const Eigen::Vector3d& local) {
  const PointJacobian J = body.point_jacobian(q, local);
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  for (int k = 0; k < J.count; ++k) velocity += J.column.col(k) * v(J.index[k]);
  return velocity;
}

// The positions of a body at t = 0 (a fixed body has none).
Eigen::VectorXd initial_positions(const BodyInstance& b) {
  return b.body->fixed() ? Eigen::VectorXd() : b.initial_position;
}

struct Cell {
  std::size_t body;     // index in drawn_
  std::int64_t shape;   // in the body's shapes, −1 for a point's vertex
  std::vector<int> points;  // indices into the file's points
};

}  // namespace

BodyShapes::BodyShapes(const World& world, VtkEncoding encoding) : world_(world), encoding_(encoding) {
  for (int i = 0; i < static_cast<int>(world.bodies.size()); ++i)
    if (!world.bodies[i].body->elastic()) drawn_.push_back(i);

  // The scene's extent at t = 0, for the halfspaces' patches: every point of the other outlines, the
  // bodies without shapes, and the elastic meshes' nodes.
  OutlineSettings settings;
  settings.dimension = world.dimension;
  std::vector<Eigen::Vector3d> extent;
  for (const BodyInstance& b : world.bodies) {
    if (const FeBody* fe = b.body->finite_elements()) {
      extent.insert(extent.end(), fe->mesh().nodes.begin(), fe->mesh().nodes.end());
      continue;
    }
    const Eigen::Isometry3d pose = b.body->pose(initial_positions(b));
    if (b.shapes.empty()) extent.push_back(pose.translation());
    for (const ShapeInstance& s : b.shapes) {
      if (std::holds_alternative<Halfspace>(s.shape)) continue;
      for (const Eigen::Vector3d& p : shape_outline(s.shape, settings).points) extent.push_back(pose * s.local_pose * p);
    }
  }

  std::vector<Cell> verts, lines, polys;
  first_point_.push_back(0);
  for (std::size_t k = 0; k < drawn_.size(); ++k) {
    const BodyInstance& b = world.bodies[drawn_[k]];
    if (b.shapes.empty()) {
      verts.push_back({k, -1, {static_cast<int>(local_points_.size())}});
      local_points_.push_back(Eigen::Vector3d::Zero());
    }
    for (std::size_t s = 0; s < b.shapes.size(); ++s) {
      const ShapeInstance& shape = b.shapes[s];
      if (const Halfspace* h = std::get_if<Halfspace>(&shape.shape)) {
        const Eigen::Vector3d centre = b.body->pose(initial_positions(b)) * shape.local_pose *
                                       (h->offset * h->normal.normalized());
        double reach = 0.0;
        for (const Eigen::Vector3d& p : extent) reach = std::max(reach, (p - centre).norm());
        settings.halfspace_half_side = reach > 0.0 ? 1.5 * reach : 1.0;
      }
      const ShapeOutline outline = shape_outline(shape.shape, settings);
      const int first = static_cast<int>(local_points_.size());
      for (const Eigen::Vector3d& p : outline.points) local_points_.push_back(shape.local_pose * p);
      const auto shifted = [first](std::vector<int> indices) {
        for (int& i : indices) i += first;
        return indices;
      };
      for (const auto& line : outline.lines) lines.push_back({k, static_cast<std::int64_t>(s), shifted(line)});
      for (const auto& polygon : outline.polygons) polys.push_back({k, static_cast<std::int64_t>(s), shifted(polygon)});
    }
    first_point_.push_back(local_points_.size());
  }

  verts_ = verts.size();
  lines_ = lines.size();
  polys_ = polys.size();
  cells_ = verts_ + lines_ + polys_;
  std::vector<std::int64_t> body, shape;
  const auto encode_cells = [&](const std::vector<Cell>& cells, EncodedArray& connectivity, EncodedArray& offsets) {
    std::vector<std::int64_t> indices, ends;
    for (const Cell& c : cells) {
      indices.insert(indices.end(), c.points.begin(), c.points.end());
      ends.push_back(static_cast<std::int64_t>(indices.size()));
      cell_body_.push_back(c.body);
      body.push_back(drawn_[c.body]);
      shape.push_back(c.shape);
    }
    connectivity = encode_array(encoding, "Int64", "connectivity", 1, indices);
    offsets = encode_array(encoding, "Int64", "offsets", 1, ends);
  };
  encode_cells(verts, verts_connectivity_, verts_offsets_);  // VTK's order of a PolyData's cells
  encode_cells(lines, lines_connectivity_, lines_offsets_);
  encode_cells(polys, polys_connectivity_, polys_offsets_);
  body_ = encode_array(encoding, "Int64", "body", 1, body);
  shape_ = encode_array(encoding, "Int64", "shape", 1, shape);
  std::vector<std::string> names;
  for (const BodyInstance& b : world.bodies) names.push_back(b.name);
  field_data_ = string_array("body_name", names);
}

BodyShapes::Sample BodyShapes::sample(const State& state) const {
  Sample out;
  out.poses.reserve(drawn_.size());
  out.velocities.reserve(drawn_.size());
  for (const int i : drawn_) {
    const BodyInstance& b = world_.bodies[i];
    const Eigen::VectorXd q = b.positions(state.q);
    const Eigen::VectorXd v = state.v.segment(b.velocity_offset, b.body->velocity_size());
    out.poses.push_back(b.body->pose(q));
    Eigen::Matrix<double, 3, 4> u;
    u.col(0) = point_velocity(*b.body, q, v, Eigen::Vector3d::Zero());
    for (int k = 0; k < 3; ++k) u.col(k + 1) = point_velocity(*b.body, q, v, Eigen::Vector3d::Unit(k));
    out.velocities.push_back(u);
  }
  return out;
}

void BodyShapes::write(VtkFileText& file, const Sample& sample, double t) const {
  std::vector<double> points(3 * local_points_.size()), velocity(3 * local_points_.size()),
      body_velocity(3 * cells_);
  for (std::size_t k = 0; k < drawn_.size(); ++k) {
    const Eigen::Isometry3d& pose = sample.poses[k];
    const Eigen::Matrix<double, 3, 4>& field = sample.velocities[k];
    const Eigen::Matrix3d gradient = field.rightCols<3>().colwise() - field.col(0);  // ∂u/∂p, body frame
    for (std::size_t p = first_point_[k]; p < first_point_[k + 1]; ++p) {
      const Eigen::Vector3d x = pose * local_points_[p];
      const Eigen::Vector3d u = field.col(0) + gradient * local_points_[p];
      std::copy(x.data(), x.data() + 3, points.begin() + 3 * p);
      std::copy(u.data(), u.data() + 3, velocity.begin() + 3 * p);
    }
  }
  for (std::size_t c = 0; c < cells_; ++c) {
    const Eigen::Vector3d u = sample.velocities[cell_body_[c]].col(0);
    std::copy(u.data(), u.data() + 3, body_velocity.begin() + 3 * c);
  }

  file.open_dataset("PolyData", "", t, field_data_);
  file.xml() += "    <Piece NumberOfPoints=\"" + std::to_string(local_points_.size()) + "\" NumberOfVerts=\"" +
         std::to_string(verts_) + "\" NumberOfLines=\"" + std::to_string(lines_) +
         "\" NumberOfStrips=\"0\" NumberOfPolys=\"" + std::to_string(polys_) + "\">\n";
  file.xml() += "      <PointData Vectors=\"velocity\">\n";
  file.array(encode_array(encoding_, "Float64", "velocity", 3, velocity));
  file.xml() += "      </PointData>\n      <CellData Scalars=\"body\">\n";
  file.array(body_);
  file.array(shape_);
  file.array(encode_array(encoding_, "Float64", "body_velocity", 3, body_velocity));
  file.xml() += "      </CellData>\n      <Points>\n";
  file.array(encode_array(encoding_, "Float64", "", 3, points));
  file.xml() += "      </Points>\n      <Verts>\n";
  file.array(verts_connectivity_);
  file.array(verts_offsets_);
  file.xml() += "      </Verts>\n      <Lines>\n";
  file.array(lines_connectivity_);
  file.array(lines_offsets_);
  file.xml() += "      </Lines>\n      <Polys>\n";
  file.array(polys_connectivity_);
  file.array(polys_offsets_);
  file.xml() += "      </Polys>\n    </Piece>\n  </PolyData>\n";
}

std::string BodyShapes::text(const Sample& sample, double t) const {
  VtkFileText file(encoding_);
  write(file, sample, t);
  return file.finish();
}

}  // namespace csim
