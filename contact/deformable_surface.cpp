#include "contact/deformable_surface.h"

#include <cmath>
#include <limits>

namespace csim {

namespace {

// Signed distance of x to the shape (m, positive outside), the closest surface point, and the
// shape's outward unit normal there.
struct Projection {
  double distance;
  Eigen::Vector3d point, normal;
};

Projection project(const Eigen::Vector3d& x, const Shape& shape, const Eigen::Isometry3d& pose, bool planar) {
  if (const auto* halfspace = std::get_if<Halfspace>(&shape)) {
    const Eigen::Vector3d n = pose.linear() * halfspace->normal;
    const double offset = halfspace->offset + n.dot(pose.translation());
    const double d = n.dot(x) - offset;
    return {d, x - d * n, n};
  }
  if (const auto* sphere = std::get_if<Sphere>(&shape)) {
    Eigen::Vector3d r = x - pose.translation();
    if (planar) r.z() = 0.0;
    const double length = r.norm();
    const Eigen::Vector3d n = length > 0.0 ? Eigen::Vector3d(r / length) : Eigen::Vector3d::UnitY();
    return {length - sphere->radius, pose.translation() + sphere->radius * n, n};
  }
  // Box: outside, the clamped point; inside, the nearest face.
  const Box& box = std::get<Box>(shape);
  Eigen::Vector3d local = pose.inverse() * x;
  Eigen::Vector3d h = box.half_extents;
  if (planar) h.z() = std::numeric_limits<double>::infinity(), local.z() = 0.0;
  const Eigen::Vector3d clamped = local.cwiseMax(-h).cwiseMin(h);
  if ((clamped - local).squaredNorm() > 0.0) {
    const Eigen::Vector3d n = (local - clamped).normalized();
    return {(local - clamped).norm(), pose * clamped, pose.linear() * n};
  }
  int axis = 0;
  double depth = std::numeric_limits<double>::infinity();
  for (int i = 0; i < (planar ? 2 : 3); ++i) {
    const double to_face = h(i) - std::abs(local(i));
    if (to_face < depth) depth = to_face, axis = i;
  }
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  n(axis) = local(axis) >= 0.0 ? 1.0 : -1.0;
  Eigen::Vector3d on_face = local;
  on_face(axis) = n(axis) * h(axis);
  return {-depth, pose * on_face, pose.linear() * n};
}

}  // namespace

void node_shape_contact(const Eigen::Vector3d& x, int node, const Shape& shape, const Eigen::Isometry3d& pose,
                        double margin, bool surface_is_a, bool planar, std::vector<ContactPoint>& out) {
  const Projection p = project(x, shape, pose, planar);
  if (p.distance > margin) return;
  ContactPoint& c = out.emplace_back();
  c.key.feature = node;
  c.gap = p.distance;
  // The shape's outward normal points from the shape to the node.
  if (surface_is_a) {
    c.point_a = x;
    c.point_b = p.point;
    c.normal = -p.normal;
  } else {
    c.point_a = p.point;
    c.point_b = x;
    c.normal = p.normal;
  }
  if (planar) {
    c.normal.z() = 0.0;
    c.normal.normalize();
    c.point_a.z() = c.point_b.z() = 0.0;
  }
}

}  // namespace csim
