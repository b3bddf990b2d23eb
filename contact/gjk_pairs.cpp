#include "contact/gjk_pairs.h"

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#include <algorithm>

namespace csim {

namespace {

// Below this GJK separation (m) the witness points no longer fix the normal (gjk_pairs.h).
constexpr double kTouchingGap = 1e-6;
// The separation (m) at which touching or overlapping shapes are measured instead.
constexpr double kProbeGap = 1e-5;
// Translations tried before giving up on separating an overlapping pair (each twice the last).
constexpr int kMaxPulls = 8;

const fcl::DistanceRequestd& distance_request() {
  static const fcl::DistanceRequestd request = [] {
    fcl::DistanceRequestd r;
    r.enable_nearest_points = true;
    r.enable_signed_distance = false;
    r.gjk_solver_type = fcl::GST_LIBCCD;
    r.distance_tolerance = 1e-12;
    return r;
  }();
  return request;
}

// GJK's distance between first and second at `second_pose` (negative: FCL found them overlapping;
// the witness points are then not meaningful, but for capsule–capsule).
double gjk_distance(const CollisionShape& first, const CollisionShape& second,
                    const Eigen::Isometry3d& second_pose, PairQuery& query) {
  auto& result = query.fcl.distance_result;
  result.clear();
  fcl::distance(first.geometry.get(), first.pose, second.geometry.get(), second_pose, distance_request(),
                result);
  return result.min_distance;
}

// A unit direction from first to second that GJK's witness points or the line of centres give.
Eigen::Vector3d separating_guess(const CollisionShape& first, const CollisionShape& second,
                                 const Eigen::Vector3d& witness) {
  if (witness.norm() > 0.0) return witness.normalized();
  const Eigen::Vector3d centres = second.pose.translation() - first.pose.translation();
  if (centres.norm() > 0.0) return centres.normalized();
  return Eigen::Vector3d::UnitX();  // concentric: any fixed direction keeps the result deterministic
}

}  // namespace

void gjk_pair(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
              std::vector<ContactPoint>& out) {
  const double gap = gjk_distance(first, second, second.pose, query);
  if (gap > query.margin) return;
  const auto& witness = query.fcl.distance_result.nearest_points;
  if (gap >= kTouchingGap) {
    add_contact(witness[0], witness[1], (witness[1] - witness[0]).normalized(), gap, 0, out);
    return;
  }

  // Touching or overlapping: directions u to translate along, by s, to a gap of about kProbeGap.
  Eigen::Vector3d guesses[3];
  double starts[3] = {kProbeGap, kProbeGap, kProbeGap};
  int guess_count = 0;
  if (gap < 0.0) {
    auto& collision = query.fcl.collision_result;
    collision.clear();
    fcl::collide(first.geometry.get(), first.pose, second.geometry.get(), second.pose,
                 query.fcl.collision_request, collision);
    if (collision.numContacts() > 0 && collision.getContact(0).normal.norm() > 0.0) {
      guesses[guess_count] = collision.getContact(0).normal.normalized();  // from first to second
      starts[guess_count++] += std::max(collision.getContact(0).penetration_depth, 0.0);
    }
  }
  // MPR's normal of two touching faces may lie in their plane, and so may the witness direction of
  // two faces a round-off apart, where no translation separates them: then the line of centres.
  if (gap >= 0.0 && (witness[1] - witness[0]).norm() > 0.0) guesses[guess_count++] = (witness[1] - witness[0]).normalized();
  guesses[guess_count++] = separating_guess(first, second, Eigen::Vector3d::Zero());
  for (int g = 0; g < guess_count; ++g) {
    Eigen::Vector3d u = guesses[g];
    double s = starts[g];
    // The first separation measures the normal n; a second one along n makes u = n to GJK's precision,
    // where the guess may be far off (coincident witness points, MPR's normal on curved shapes).
    bool refined = false;
    for (int pull = 0; pull < kMaxPulls; ++pull) {
      Eigen::Isometry3d moved = second.pose;
      moved.translation() += s * u;
      const double measured = gjk_distance(first, second, moved, query);
      if (measured <= 0.0) {  // still overlapping along u: go further
        s *= 2.0;
        continue;
      }
      const Eigen::Vector3d n = (witness[1] - witness[0]).normalized();
      const double contact_gap = measured - s * u.dot(n);
      if (!refined) {
        refined = true;
        u = n;
        s = kProbeGap + std::max(-contact_gap, 0.0);
        continue;
      }
      if (contact_gap > query.margin) return;
      const Eigen::Vector3d on_second = witness[1] - s * u;
      add_contact(on_second - contact_gap * n, on_second, n, contact_gap, 0, out);
      return;
    }
  }
  // Not reached for convex shapes of positive size and a guess with a component along the normal.
}

}  // namespace csim
