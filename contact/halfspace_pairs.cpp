#include "contact/halfspace_pairs.h"

#include <cmath>

namespace csim {

namespace {

constexpr double kPi = 3.14159265358979323846;

// A contact of a point of the first shape at `point` (world) with the plane, if its gap ≤ margin;
// `arm` (world, from the shape's origin) when the point is a material one.
void add_plane_contact(const Eigen::Vector3d& point, const WorldPlane& plane, double margin, int feature,
                       const Eigen::Vector3d* arm, std::vector<ContactPoint>& out) {
  const double gap = plane.normal.dot(point) - plane.offset;
  if (gap > margin) return;
  // The shape looks into the halfspace: normal −n; the plane point is the point's projection.
  add_contact(point, point - gap * plane.normal, -plane.normal, gap, feature, out);
  if (arm) out.back().arm_a = *arm;
}

}  // namespace

Eigen::Vector3d cylinder_rim_point(const Cylinder& cylinder, int rim, int j) {
  const double angle = 2.0 * kPi * j / kRimPoints;
  return {cylinder.radius * std::cos(angle), cylinder.radius * std::sin(angle),
          rim == 0 ? -cylinder.half_length : cylinder.half_length};
}

void capsule_halfspace(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
                       std::vector<ContactPoint>& out) {
  const Capsule& capsule = std::get<Capsule>(first.shape);
  const WorldPlane plane = world_plane(second);
  const Eigen::Vector3d axis = first.pose.linear().col(2);
  const Eigen::Vector3d c = first.pose.translation();
  for (int end = 0; end < 2; ++end) {
    const Eigen::Vector3d centre = c + (end == 0 ? -capsule.half_length : capsule.half_length) * axis;
    add_plane_contact(centre - capsule.radius * plane.normal, plane, query.margin, end, nullptr, out);
  }
}

void cylinder_halfspace(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
                        std::vector<ContactPoint>& out) {
  const Cylinder& cylinder = std::get<Cylinder>(first.shape);
  const WorldPlane plane = world_plane(second);
  const Eigen::Matrix3d& R = first.pose.linear();
  const Eigen::Vector3d c = first.pose.translation();
  const Eigen::Vector3d axis = R.col(2);
  // The normal's part across the axis: the direction of the rims' lowest points is its opposite.
  const Eigen::Vector3d across = plane.normal - plane.normal.dot(axis) * axis;
  const double sin_tilt = across.norm();
  // Lowest point height, exact: skips the rim loop for cylinders well above the plane.
  const double reach = cylinder.half_length * std::abs(plane.normal.dot(axis)) + cylinder.radius * sin_tilt;
  if (plane.normal.dot(c) - plane.offset - reach > query.margin) return;

  for (int rim = 0; rim < 2 && std::abs(plane.normal.dot(axis)) >= kFaceDown; ++rim) {
    for (int j = 0; j < kRimPoints; ++j) {
      const Eigen::Vector3d arm = R * cylinder_rim_point(cylinder, rim, j);
      add_plane_contact(arm + c, plane, query.margin, kRimPoints * rim + j, &arm, out);
    }
  }
  if (sin_tilt <= kUprightTilt) return;
  const Eigen::Vector3d outward = -across / sin_tilt;  // from the axis to the lowest rim points
  for (int rim = 0; rim < 2; ++rim) {
    const Eigen::Vector3d rim_centre = c + (rim == 0 ? -cylinder.half_length : cylinder.half_length) * axis;
    add_plane_contact(rim_centre + cylinder.radius * outward, plane, query.margin, 2 * kRimPoints + rim,
                      nullptr, out);
  }
}

void convex_halfspace(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
                      std::vector<ContactPoint>& out) {
  const Convex& convex = std::get<Convex>(first.shape);
  const WorldPlane plane = world_plane(second);
  const Eigen::Matrix3d& R = first.pose.linear();
  const Eigen::Vector3d c = first.pose.translation();
  for (std::size_t i = 0; i < convex.vertices.size(); ++i) {
    const Eigen::Vector3d arm = R * convex.vertices[i];  // a vertex is a material point of the hull
    add_plane_contact(arm + c, plane, query.margin, static_cast<int>(i), &arm, out);
  }
}

}  // namespace csim
