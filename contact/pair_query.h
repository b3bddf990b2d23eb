// What the narrow phase's pair functions share (internal to contact/: included by narrow_phase.cpp and
// the pair files beside it, never by a public header, because NarrowPhase exposes FCL types).
//
// A pair function appends the contacts between `first` and `second` whose gap ≤ query.margin (m):
// normal from first to second, points, gap and feature set; keys, frames and the planar projection
// are left to NarrowPhase::collide (contact_point.h for the sign conventions).
#pragma once

#include "contact/contact_point.h"
#include "contact/narrow_phase.h"

#include <variant>
#include <vector>

namespace csim {

struct PairQuery {
  double margin;  // m
  NarrowPhase::FclScratch& fcl;
};

using PairFunction = void (*)(const CollisionShape& first, const CollisionShape& second,
                              PairQuery& query, std::vector<ContactPoint>& out);

inline void add_contact(const Eigen::Vector3d& point_first, const Eigen::Vector3d& point_second,
                        const Eigen::Vector3d& normal, double gap, int feature,
                        std::vector<ContactPoint>& out) {
  ContactPoint& c = out.emplace_back();
  c.key.feature = feature;
  c.point_a = point_first;
  c.point_b = point_second;
  c.normal = normal;
  c.gap = gap;
}

// The halfspace { x : n·x ≤ offset } in world coordinates (unit n).
struct WorldPlane {
  Eigen::Vector3d normal;
  double offset;  // m
};

inline WorldPlane world_plane(const CollisionShape& instance) {
  const auto& halfspace = std::get<Halfspace>(instance.shape);
  const Eigen::Vector3d n = instance.pose.linear() * halfspace.normal;
  return {n, halfspace.offset + n.dot(instance.pose.translation())};
}

}  // namespace csim
