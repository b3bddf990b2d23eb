#include "contact/convex_manifold.h"


#include <algorithm>
#include <cmath>

namespace csim {

namespace {

// The reference chosen: whose, and its outward normal (towards the incident shape); its feature is
// left in scratch.reference.
struct Reference {
  bool is_first = true;
  bool segment = false;  // a segment across the normal rather than a face along it
  Eigen::Vector3d normal;
};

// A point of the line a segment across the normal is drawn from: a capsule's or a cylinder's axis
// (its segment is the axis pushed out by the radius), a box's or a hull's edge itself.
Eigen::Vector3d core_point(const Shape& shape, const Eigen::Isometry3d& pose, const SupportFeature& segment) {
  if (std::holds_alternative<Capsule>(shape) || std::holds_alternative<Cylinder>(shape)) return pose.translation();
  return segment.points[0];
}

// The unit normal across two parallel segments, out of the reference: the part across the reference's
// `axis` of the vector from the reference's core line to the incident's, both taken at the middle of
// the segments' overlap along `axis`. Exact for parallel lines, where FCL's normal is GJK's for a box or
// a hull (1e-6 to 1e-5 rad off, gjk_pairs.h). `fallback` (FCL's, made across `axis`) where the two
// lines meet (the cores overlap) or that vector points against it.
Eigen::Vector3d across_normal(const Eigen::Vector3d& axis, const Eigen::Vector3d& reference_core,
                              const SupportFeature& reference, const Eigen::Vector3d& incident_core,
                              const SupportFeature& incident, const Eigen::Vector3d& fallback) {
  Eigen::Vector3d incident_axis = (incident.points[1] - incident.points[0]).normalized();
  if (incident_axis.dot(axis) < 0.0) incident_axis = -incident_axis;
  const double r0 = axis.dot(reference.points[0]), r1 = axis.dot(reference.points[1]);
  const double i0 = axis.dot(incident.points[0]), i1 = axis.dot(incident.points[1]);
  const double middle = 0.5 * (std::max(std::min(r0, r1), std::min(i0, i1)) + std::min(std::max(r0, r1), std::max(i0, i1)));
  const Eigen::Vector3d on_reference = reference_core + (middle - axis.dot(reference_core)) * axis;
  const Eigen::Vector3d on_incident =
      incident_core + (middle - axis.dot(incident_core)) / incident_axis.dot(axis) * incident_axis;
  const Eigen::Vector3d between = on_incident - on_reference;
  const Eigen::Vector3d across = between - between.dot(axis) * axis;
  const double size = std::max(reference.size, incident.size);
  if (!(across.norm() > 1e-9 * size) || across.dot(fallback) <= 0.0) return fallback;
  return across.normalized();
}

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
  // Two parallel segments across the normal (capsules' cores, cylinders' side generators, boxes' and
  // hulls' edges: no face is along it here).
  if (!segment_across(first, first_pose, normal, planar, on_first)) return false;
  if (!segment_across(second, second_pose, -normal, planar, on_second)) return false;
  const Eigen::Vector3d first_axis = (on_first.points[1] - on_first.points[0]).normalized();
  const Eigen::Vector3d second_axis = (on_second.points[1] - on_second.points[0]).normalized();
  if (first_axis.cross(second_axis).norm() > kAcrossAlignment) return false;  // crossing: one point
  reference.is_first = on_first.size >= on_second.size;
  reference.segment = true;
  const Eigen::Vector3d& axis = reference.is_first ? first_axis : second_axis;
  const Eigen::Vector3d outward = reference.is_first ? normal : Eigen::Vector3d(-normal);
  const Shape& shape = reference.is_first ? first : second;
  const Eigen::Isometry3d& pose = reference.is_first ? first_pose : second_pose;
  const Shape& other = reference.is_first ? second : first;
  const Eigen::Isometry3d& other_pose = reference.is_first ? second_pose : first_pose;
  const SupportFeature& segment = reference.is_first ? on_first : on_second;
  const SupportFeature& other_segment = reference.is_first ? on_second : on_first;
  reference.normal = across_normal(axis, core_point(shape, pose, segment), segment,
                                   core_point(other, other_pose, other_segment), other_segment,
                                   (outward - outward.dot(axis) * axis).normalized());
  // Again along that normal, so that the gaps are measured along it.
  return segment_across(shape, pose, reference.normal, planar, scratch.reference);
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
  // A segment meets a segment (a box's or hull's face most along the normal would be the wrong feature
  // across an edge); a face meets whatever faces it.
  const bool has_incident =
      reference.segment ? segment_across(incident_shape, incident_pose, -reference.normal, planar, scratch.incident)
                        : incident_feature(incident_shape, incident_pose, -reference.normal, planar, scratch.incident);
  if (!has_incident) return 0;

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
