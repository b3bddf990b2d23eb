#include "contact/contact_point.h"

#include <cmath>

namespace csim {

namespace {

// Below this (relative to |direction|) the direction is taken as parallel to n: its orthogonal part
// is rounding noise and would give an arbitrary t1.
constexpr double kParallelTolerance = 1e-12;

// A later axis is taken as less aligned only when it is so by more than this (|n| = 1). Built scenes are
// full of ties: a normal along an axis, or at 45° between two (a sphere on a floor, on four below it, or
// beside its neighbour in a layer). A strict comparison lets the round-off of n pick the axis, so t1
// turns by 90° from one step to the next: the warm start's tangential impulses then point the wrong way
// and W changes while nothing moves (a settled pile of 200 spheres: |ΔW|/|W| = 0.4–0.9 a step).
constexpr double kTieMargin = 1e-6;

// The world axis least aligned with n, the first one on ties to within kTieMargin, so that its
// projection is well conditioned (its orthogonal part has norm ≥ sqrt(2/3) − kTieMargin) and the
// choice depends on n only, and not on its round-off near a tie.
Eigen::Vector3d least_aligned_axis(const Eigen::Vector3d& n) {
  const Eigen::Vector3d a = n.cwiseAbs();
  int axis = 0;
  if (a.y() < a[axis] - kTieMargin) axis = 1;
  if (a.z() < a[axis] - kTieMargin) axis = 2;
  return Eigen::Vector3d::Unit(axis);
}

Eigen::Vector3d orthogonal_part(const Eigen::Vector3d& v, const Eigen::Vector3d& n) {
  return v - v.dot(n) * n;
}

}  // namespace

void complete_frame(ContactPoint& contact, bool planar, const Eigen::Vector3d& direction) {
  const Eigen::Vector3d& n = contact.normal;
  if (planar) {
    // In the plane z = 0 the only tangent is e_z × n; e_z completes the right-handed frame.
    contact.t2 = Eigen::Vector3d::UnitZ();
    contact.t1 = contact.t2.cross(n).normalized();
    return;
  }
  const double direction_norm = direction.norm();
  if (direction_norm > 0.0) {
    const Eigen::Vector3d along_direction = orthogonal_part(direction, n);
    const double along_norm = along_direction.norm();
    if (along_norm > kParallelTolerance * direction_norm) {
      contact.t1 = along_direction / along_norm;
      contact.t2 = n.cross(contact.t1);
      return;
    }
  }
  contact.t1 = orthogonal_part(least_aligned_axis(n), n).normalized();
  contact.t2 = n.cross(contact.t1);
}

}  // namespace csim
