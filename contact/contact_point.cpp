#include "contact/contact_point.h"

#include <cmath>

namespace csim {

namespace {

// Below this (relative to |direction|) the direction is taken as parallel to n: its orthogonal part
// is rounding noise and would give an arbitrary t1.
constexpr double kParallelTolerance = 1e-12;

// The world axis least aligned with n (first one on ties), so that its projection is well conditioned
// (its orthogonal part has norm ≥ sqrt(2/3)) and the choice depends on n only.
Eigen::Vector3d least_aligned_axis(const Eigen::Vector3d& n) {
  const Eigen::Vector3d a = n.cwiseAbs();
  int axis = 0;
  if (a.y() < a[axis]) axis = 1;
  if (a.z() < a[axis]) axis = 2;
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
