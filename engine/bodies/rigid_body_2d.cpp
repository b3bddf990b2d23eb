#include "engine/bodies/rigid_body_2d.h"

#include <cmath>

namespace csim {

void RigidBody2d::add_mass(int offset, Triplets& mass) const {
  mass.emplace_back(offset, offset, mass_);
  mass.emplace_back(offset + 1, offset + 1, mass_);
  mass.emplace_back(offset + 2, offset + 2, inertia_);
}

// A step asks for the same angle's rotation a dozen times (poses, points, Jacobians of springs, loads
// and contacts): its cosine and sine are kept for the last angle asked.
void RigidBody2d::cos_sin(double angle, double& c, double& s) const {
  if (angle != cached_angle_) {
    cached_angle_ = angle;
    cached_cos_ = std::cos(angle);
    cached_sin_ = std::sin(angle);
  }
  c = cached_cos_;
  s = cached_sin_;
}

// The rotation by φ about e_z, entry for entry as Eigen's AngleAxis::toRotationMatrix builds it.
Eigen::Isometry3d RigidBody2d::pose(const ConstVectorRef& q) const {
  double c, s;
  cos_sin(q(2), c, s);
  Eigen::Isometry3d pose;  // written entry for entry (a pose is asked for at every step)
  double* m = pose.matrix().data();  // column-major 4 × 4
  m[0] = c, m[1] = s, m[2] = 0.0, m[3] = 0.0;
  m[4] = -s, m[5] = c, m[6] = 0.0, m[7] = 0.0;
  m[8] = 0.0, m[9] = 0.0, m[10] = (1.0 - c) + c, m[11] = 0.0;
  m[12] = q(0), m[13] = q(1), m[14] = 0.0, m[15] = 1.0;
  return pose;
}

// pose(q) * local without forming the pose (springs and probes ask for points at every step): the
// translation plus R local, each row's products summed over R's columns in turn, as Eigen's affine
// product sums them (the terms of the zero entries included, for the same bits).
Eigen::Vector3d RigidBody2d::point_world(const ConstVectorRef& q, const Eigen::Vector3d& local) const {
  double c, s;
  cos_sin(q(2), c, s);
  const double x = local.x(), y = local.y(), z = local.z();
  return {q(0) + ((c * x + (-s) * y) + 0.0 * z), q(1) + ((s * x + c * y) + 0.0 * z),
          0.0 + ((0.0 * x + 0.0 * y) + ((1.0 - c) + c) * z)};
}

// v_point = v + ω e_z × (R r): the rotation column is e_z × (R r) = (−(Rr)_y, (Rr)_x, 0).
PointJacobian RigidBody2d::point_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& local) const {
  double c, s;
  cos_sin(q(2), c, s);
  const double rx = c * local.x() - s * local.y();
  const double ry = s * local.x() + c * local.y();
  PointJacobian J;
  J.add(0, Eigen::Vector3d::UnitX());
  J.add(1, Eigen::Vector3d::UnitY());
  J.add(2, Eigen::Vector3d(-ry, rx, 0.0));
  return J;
}

// point_world and point_jacobian with one lever arm R r: c x − s y is point_world's c x + (−s) y to
// the bit (a negation is exact).
Eigen::Vector3d RigidBody2d::point_kinematics(const ConstVectorRef& q, const Eigen::Vector3d& local,
                                              PointJacobian& J) const {
  double c, s;
  cos_sin(q(2), c, s);
  const double x = local.x(), y = local.y(), z = local.z();
  const double rx = c * x - s * y, ry = s * x + c * y;
  J.count = 0;
  J.add(0, Eigen::Vector3d::UnitX());
  J.add(1, Eigen::Vector3d::UnitY());
  J.add(2, Eigen::Vector3d(-ry, rx, 0.0));
  return {q(0) + (rx + 0.0 * z), q(1) + (ry + 0.0 * z), 0.0 + ((0.0 * x + 0.0 * y) + ((1.0 - c) + c) * z)};
}

void RigidBody2d::project_world_point_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& x,
                                               const Eigen::Vector3d* const* axes, int axis_count,
                                               ProjectedJacobian& out) const {
  project_lever_arm_jacobian(q, Eigen::Vector3d(x.x() - q(0), x.y() - q(1), 0.0), axes, axis_count, out);
}

// The rotation column e_z × r with r the world lever arm: (−r_y, r_x, 0).
void RigidBody2d::project_lever_arm_jacobian(const ConstVectorRef&, const Eigen::Vector3d& r,
                                             const Eigen::Vector3d* const* axes, int axis_count,
                                             ProjectedJacobian& out) const {
  const double rx = r.x(), ry = r.y();
  out.count = 3;
  out.ascending = true;
  for (int j = 0; j < 3; ++j) out.index[j] = j;
  for (int k = 0; k < axis_count; ++k) {
    const Eigen::Vector3d& a = *axes[k];
    out.value(k, 0) = a.x();
    out.value(k, 1) = a.y();
    out.value(k, 2) = a.y() * rx - a.x() * ry;
  }
}

void RigidBody2d::integrate_position(const ConstVectorRef& q, const ConstVectorRef& v_theta,
                                     double h, VectorRef q_next) const {
  q_next = q + h * v_theta;
}

int RigidBody2d::velocity_index(const std::string& component) const {
  if (component == "x") return 0;
  if (component == "y") return 1;
  if (component == "rz") return 2;
  return -1;
}

}  // namespace csim
