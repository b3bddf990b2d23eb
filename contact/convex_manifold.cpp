#include "contact/convex_manifold.h"


#include <algorithm>
#include <cmath>

namespace csim {

namespace {

// The reference chosen: whose, and its outward normal (towards the incident shape); its feature is
// left in scratch.reference.
struct Reference {
  bool is_first = true;
  Eigen::Vector3d normal;
};

// A face of either shape along the normal (the larger, the first's on a tie), or a pair of parallel
// segments (the longer); false when neither.
bool choose_reference(const Shape& first, const Eigen::Isometry3d& first_pose, const Shape& second,
                      const Eigen::Isometry3d& second_pose, const Eigen::Vector3d& normal, bool planar,
                      ManifoldScratch& scratch, Reference& reference) {
  SupportFeature& on_first = scratch.on_first;
  SupportFeature& on_second = scratch.on_second;
  const bool first_face = face_along(first, first_pose, normal, planar, on_first);
  const bool second_face = face_along(second, second_pose, -normal, planar, on_second);
  if (first_face || second_face) {
    reference.is_first = first_face && (!second_face || on_first.size >= on_second.size);
    std::swap(scratch.reference, reference.is_first ? on_first : on_second);  // keeps every buffer
    reference.normal = scratch.reference.normal;
    return true;
  }
  // Two segments across the normal (faces are excluded above; a box's or hull's incident feature is a
  // polygon).
  if (!incident_feature(first, first_pose, normal, planar, on_first) || on_first.count() != 2) return false;
  if (!incident_feature(second, second_pose, -normal, planar, on_second) || on_second.count() != 2) return false;
  const Eigen::Vector3d first_axis = (on_first.points[1] - on_first.points[0]).normalized();
  const Eigen::Vector3d second_axis = (on_second.points[1] - on_second.points[0]).normalized();
  if (first_axis.cross(second_axis).norm() > kAcrossAlignment) return false;  // crossing: one point
  reference.is_first = on_first.size >= on_second.size;
  const Eigen::Vector3d& axis = reference.is_first ? first_axis : second_axis;
  const Eigen::Vector3d outward = reference.is_first ? normal : Eigen::Vector3d(-normal);
  reference.normal = (outward - outward.dot(axis) * axis).normalized();
  // Again along the exact normal, so that the gaps are measured along it.
  const Shape& shape = reference.is_first ? first : second;
  const Eigen::Isometry3d& pose = reference.is_first ? first_pose : second_pose;
  return incident_feature(shape, pose, reference.normal, planar, scratch.reference) && scratch.reference.count() == 2;
}

int power_of_two_at_least(int value) {
  int p = 1;
  while (p < value) p *= 2;
  return p;
}

}  // namespace

int convex_manifold(const Shape& first, const Eigen::Isometry3d& first_pose, const Shape& second,
                    const Eigen::Isometry3d& second_pose, const Eigen::Vector3d& normal, double margin,
                    bool planar, int min_points, ManifoldScratch& scratch, std::vector<ContactPoint>& out) {
  Reference reference;
  if (!choose_reference(first, first_pose, second, second_pose, normal, planar, scratch, reference)) return 0;
  const Shape& incident_shape = reference.is_first ? second : first;
  const Eigen::Isometry3d& incident_pose = reference.is_first ? second_pose : first_pose;
  if (!incident_feature(incident_shape, incident_pose, -reference.normal, planar, scratch.incident)) return 0;

  const int id_bound = std::max(feature_id_bound(first), feature_id_bound(second));
  std::vector<ClippedPoint>& points = scratch.points;
  clip_features(scratch.reference, reference.normal, scratch.incident, margin, id_bound, scratch.clip, points);
  if (static_cast<int>(points.size()) < min_points || points.empty()) return 0;
  const int second_offset = power_of_two_at_least((id_bound + 2) * id_bound);
  for (const ClippedPoint& p : points) {
    ContactPoint& contact = out.emplace_back();
    contact.gap = p.gap;
    if (reference.is_first) {
      contact.key.feature = p.feature;
      contact.normal = reference.normal;
      contact.point_a = p.reference_point;
      contact.point_b = p.incident_point;
      contact.arm_a = p.reference_arm;
      contact.arm_b = p.incident_arm;
    } else {
      contact.key.feature = p.feature + second_offset;
      contact.normal = -reference.normal;
      contact.point_a = p.incident_point;
      contact.point_b = p.reference_point;
      contact.arm_a = p.incident_arm;
      contact.arm_b = p.reference_arm;
    }
  }
  return static_cast<int>(points.size());
}

}  // namespace csim
