#include "contact/support_features.h"

#include "contact/halfspace_pairs.h"
#include "contact/narrow_phase.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace csim {

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

void add_point(const Eigen::Isometry3d& pose, const Eigen::Vector3d& local, int id, bool material,
               SupportFeature& out) {
  const Eigen::Vector3d arm = pose.linear() * local;
  out.points.push_back(arm + pose.translation());  // pose * local, to the bit
  out.arms.push_back(material ? arm : Eigen::Vector3d::Constant(kNan));
  out.ids.push_back(id);
}

// ---- box ------------------------------------------------------------------------------------------

struct BoxFace {
  int axis = 0;
  int sign = 1;
  double cosine = -2.0;  // outward normal · direction
};

// The face whose outward normal is most along `direction` (the first on ties).
BoxFace box_face(const Eigen::Matrix3d& R, const Eigen::Vector3d& direction, bool planar) {
  BoxFace best;
  for (int k = 0; k < (planar ? 2 : 3); ++k) {
    const double c = R.col(k).dot(direction);
    if (std::abs(c) > best.cosine) best = {k, c > 0.0 ? 1 : -1, std::abs(c)};
  }
  return best;
}

int box_vertex_index(const std::array<int, 3>& signs) {
  return (signs[0] > 0 ? 1 : 0) | (signs[1] > 0 ? 2 : 0) | (signs[2] > 0 ? 4 : 0);
}

void box_face_feature(const Box& box, const Eigen::Isometry3d& pose, const BoxFace& face, bool planar,
                      SupportFeature& out) {
  out.clear();
  const Eigen::Vector3d& h = box.half_extents;
  std::array<int, 3> signs{};
  signs[face.axis] = face.sign;
  out.normal = face.sign * pose.linear().col(face.axis);
  if (planar) {  // the edge of the z = 0 section
    const int u = 1 - face.axis;
    for (int c : {-1, 1}) {
      signs[u] = c;
      const int v = box_vertex_index(signs);
      add_point(pose, box_vertex(box, v, true), v, true, out);
    }
    out.size = 2.0 * h[u];
    return;
  }
  const int i = (face.axis + 1) % 3;
  const int j = (face.axis + 2) % 3;
  constexpr int kCycle[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (const auto& corner : kCycle) {
    signs[i] = corner[0];
    signs[j] = corner[1];
    const int v = box_vertex_index(signs);
    add_point(pose, box_vertex(box, v, false), v, true, out);
  }
  out.size = 4.0 * h[i] * h[j];
}

// The box's edge across `direction` farthest along it: along the box axis k with |R_k·d| ≤
// kAcrossAlignment, on the side of each other axis that d points to. False when no axis is across d,
// and in plane scenes (a box's section has no edge across the plane's normals but its corners).
bool box_edge(const Box& box, const Eigen::Isometry3d& pose, const Eigen::Vector3d& direction, bool planar,
              SupportFeature& out) {
  if (planar) return false;
  const Eigen::Vector3d cosines = pose.linear().transpose() * direction;
  int k = 0;
  cosines.cwiseAbs().minCoeff(&k);
  if (std::abs(cosines[k]) > kAcrossAlignment) return false;
  out.clear();
  std::array<int, 3> signs{};
  for (int i = 0; i < 3; ++i) signs[i] = cosines[i] > 0.0 ? 1 : -1;
  for (int end : {-1, 1}) {
    signs[k] = end;
    const int v = box_vertex_index(signs);
    add_point(pose, box_vertex(box, v, false), v, true, out);
  }
  out.size = 2.0 * box.half_extents[k];
  return true;
}

// ---- convex hull ----------------------------------------------------------------------------------

// The hull's face most along `direction` (world): the polygon (cached by make_convex) of largest
// normal·direction, the first on ties. Returns that cosine.
double hull_face(const Convex& hull, const Eigen::Isometry3d& pose, const Eigen::Vector3d& direction,
                 SupportFeature& out) {
  out.clear();
  const Eigen::Vector3d local = pose.linear().transpose() * direction;
  std::size_t best = 0;
  double best_cosine = -2.0;
  for (std::size_t f = 0; f < hull.polygons.size(); ++f) {
    const double c = hull.polygons[f].normal.dot(local);
    if (c > best_cosine) best_cosine = c, best = f;
  }
  const ConvexFace& face = hull.polygons[best];
  for (int v : face.vertices) add_point(pose, hull.vertices[v], v, true, out);
  out.normal = pose.linear() * face.normal;
  out.size = face.area;
  return best_cosine;
}

// The hull's edge across `direction` (world) that reaches farthest along it: of the edges whose
// direction e has |e·d| ≤ kAcrossAlignment and whose ends both lie within kAcrossAlignment × the
// edge's length (plus 1e-9 of the hull's reach) of the hull's support height, the one of the largest
// summed height of its ends (the first on ties). False when there is none (a vertex is the support).
bool hull_edge(const Convex& hull, const Eigen::Isometry3d& pose, const Eigen::Vector3d& direction,
               SupportFeature& out) {
  const Eigen::Vector3d local = pose.linear().transpose() * direction;
  double top = -std::numeric_limits<double>::infinity(), reach = 0.0;
  for (const Eigen::Vector3d& x : hull.vertices) top = std::max(top, x.dot(local)), reach = std::max(reach, x.norm());
  int best = -1;
  double best_height = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < hull.edges.size(); ++k) {
    const Eigen::Vector3d& a = hull.vertices[hull.edges[k][0]];
    const Eigen::Vector3d& b = hull.vertices[hull.edges[k][1]];
    const double length = (b - a).norm();
    const double slack = kAcrossAlignment * length + 1e-9 * reach;
    const double ha = a.dot(local), hb = b.dot(local);
    if (std::abs(hb - ha) > kAcrossAlignment * length || ha < top - slack || hb < top - slack) continue;
    if (ha + hb > best_height) best_height = ha + hb, best = static_cast<int>(k);
  }
  if (best < 0) return false;
  out.clear();
  for (int v : hull.edges[best]) add_point(pose, hull.vertices[v], v, true, out);
  out.size = (hull.vertices[hull.edges[best][1]] - hull.vertices[hull.edges[best][0]]).norm();
  return true;
}

// ---- cylinder and capsule -------------------------------------------------------------------------

void cylinder_cap(const Cylinder& cylinder, const Eigen::Isometry3d& pose, int rim, SupportFeature& out) {
  out.clear();
  for (int j = 0; j < kRimPoints; ++j)
    add_point(pose, cylinder_rim_point(cylinder, rim, j), kRimPoints * rim + j, true, out);
  out.normal = (rim == 0 ? -1.0 : 1.0) * pose.linear().col(2);
  // The polygon of kRimPoints points on a circle of radius r: (k/2) r² sin(2π/k).
  out.size = 0.5 * kRimPoints * cylinder.radius * cylinder.radius * std::sin(2.0 * 3.14159265358979323846 / kRimPoints);
}

// The segment of the two points, each `reach` from an end of the core segment along `outward`.
void pushed_out_segment(const Eigen::Isometry3d& pose, double half_length, double reach,
                        const Eigen::Vector3d& outward, int first_id, SupportFeature& out) {
  out.clear();
  const Eigen::Vector3d axis = pose.linear().col(2);
  for (int end = 0; end < 2; ++end) {
    const Eigen::Vector3d centre = pose.translation() + (end == 0 ? -half_length : half_length) * axis;
    out.points.push_back(centre + reach * outward);
    out.arms.push_back(Eigen::Vector3d::Constant(kNan));
    out.ids.push_back(first_id + end);
  }
  out.size = 2.0 * half_length;
}

}  // namespace

bool face_along(const Shape& shape, const Eigen::Isometry3d& pose, const Eigen::Vector3d& direction, bool planar,
                SupportFeature& out) {
  if (const auto* box = std::get_if<Box>(&shape)) {
    const BoxFace face = box_face(pose.linear(), direction, planar);
    if (1.0 - face.cosine > kFaceAlignment) return false;
    box_face_feature(*box, pose, face, planar, out);
    return true;
  }
  if (const auto* hull = std::get_if<Convex>(&shape)) return 1.0 - hull_face(*hull, pose, direction, out) <= kFaceAlignment;
  if (const auto* cylinder = std::get_if<Cylinder>(&shape)) {
    const double c = pose.linear().col(2).dot(direction);
    if (1.0 - std::abs(c) > kFaceAlignment) return false;
    cylinder_cap(*cylinder, pose, c > 0.0 ? 1 : 0, out);
    return true;
  }
  return false;
}

bool segment_across(const Shape& shape, const Eigen::Isometry3d& pose, const Eigen::Vector3d& direction,
                    bool planar, SupportFeature& out) {
  if (const auto* box = std::get_if<Box>(&shape)) return box_edge(*box, pose, direction, planar, out);
  if (const auto* hull = std::get_if<Convex>(&shape)) return hull_edge(*hull, pose, direction, out);
  const Eigen::Vector3d axis = pose.linear().col(2);
  const double along = axis.dot(direction);
  if (std::abs(along) > kAcrossAlignment) return false;
  if (const auto* cylinder = std::get_if<Cylinder>(&shape)) {
    // The generator farthest along `direction`: from the axis along direction's part across it.
    const Eigen::Vector3d outward = (direction - along * axis).normalized();
    pushed_out_segment(pose, cylinder->half_length, cylinder->radius, outward, 2 * kRimPoints, out);
    return true;
  }
  if (const auto* capsule = std::get_if<Capsule>(&shape)) {
    if (capsule->half_length <= 0.0) return false;
    // The cap spheres' points farthest along `direction`: exact at any angle of the axis.
    pushed_out_segment(pose, capsule->half_length, capsule->radius, direction, 0, out);
    return true;
  }
  return false;
}

bool incident_feature(const Shape& shape, const Eigen::Isometry3d& pose, const Eigen::Vector3d& direction,
                      bool planar, SupportFeature& out) {
  if (const auto* box = std::get_if<Box>(&shape)) {
    box_face_feature(*box, pose, box_face(pose.linear(), direction, planar), planar, out);
    return true;
  }
  if (const auto* hull = std::get_if<Convex>(&shape)) {
    hull_face(*hull, pose, direction, out);
    return true;
  }
  if (const auto* cylinder = std::get_if<Cylinder>(&shape)) {
    const double along = pose.linear().col(2).dot(direction);
    if (1.0 - std::abs(along) <= kFaceAlignment) {
      cylinder_cap(*cylinder, pose, along > 0.0 ? 1 : 0, out);
      return true;
    }
  }
  return segment_across(shape, pose, direction, planar, out);
}

int feature_id_bound(const Shape& shape) {
  if (std::holds_alternative<Box>(shape)) return 8;
  if (std::holds_alternative<Cylinder>(shape)) return 2 * kRimPoints + 2;
  if (std::holds_alternative<Capsule>(shape)) return 2;
  if (const auto* hull = std::get_if<Convex>(&shape)) return static_cast<int>(hull->vertices.size());
  return 1;
}

}  // namespace csim
