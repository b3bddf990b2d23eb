#include "engine/bodies/rigid_body_3d.h"

#include "engine/linear_algebra/same_bits.h"

#include <cstring>

namespace csim {

namespace {
Eigen::Quaterniond orientation(const ConstVectorRef& q) {
  return Eigen::Quaterniond(q(3), q(4), q(5), q(6));
}
}  // namespace

void RigidBody3d::add_mass(int offset, Triplets& mass) const {
  for (int i = 0; i < 3; ++i) mass.emplace_back(offset + i, offset + i, mass_);
  for (int i = 0; i < 3; ++i) mass.emplace_back(offset + 3 + i, offset + 3 + i, inertia_(i));
}

const Eigen::Matrix3d& RigidBody3d::rotation(const ConstVectorRef& q) const {
  const double quaternion[4] = {q(3), q(4), q(5), q(6)};
  if (!rotation_cached_ || !same_bits(quaternion, cached_quaternion_, 4)) {
    std::memcpy(cached_quaternion_, quaternion, sizeof quaternion);
    cached_rotation_ = orientation(q).normalized().toRotationMatrix();
    rotation_cached_ = true;
  }
  return cached_rotation_;
}

Eigen::Isometry3d RigidBody3d::pose(const ConstVectorRef& q) const {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = q.head<3>();
  pose.linear() = rotation(q);
  return pose;
}

// v_point = v + R(ω × r) = v − R [r]× ω.
PointJacobian RigidBody3d::point_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& local) const {
  const Eigen::Matrix3d& R = rotation(q);
  Eigen::Matrix3d r_cross;
  r_cross << 0, -local.z(), local.y(), local.z(), 0, -local.x(), -local.y(), local.x(), 0;
  const Eigen::Matrix3d rotation_columns = -R * r_cross;
  PointJacobian J;
  for (int i = 0; i < 3; ++i) J.add(i, Eigen::Vector3d::Unit(i));
  for (int i = 0; i < 3; ++i) J.add(3 + i, rotation_columns.col(i));
  return J;
}

void RigidBody3d::project_world_point_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& x,
                                               const Eigen::Vector3d* const* axes, int axis_count,
                                               ProjectedJacobian& out) const {
  project_lever_arm_jacobian(q, x - q.head<3>(), axes, axis_count, out);
}

// a · (R_i × r) = R_i · (r × a), r the world lever arm: a translation column's projection is a itself,
// a rotation column's R_i · (r × a).
void RigidBody3d::project_lever_arm_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& r,
                                             const Eigen::Vector3d* const* axes, int axis_count,
                                             ProjectedJacobian& out) const {
  const Eigen::Matrix3d& R = rotation(q);
  out.count = 6;
  out.ascending = true;
  for (int j = 0; j < 6; ++j) out.index[j] = j;
  for (int k = 0; k < axis_count; ++k) {
    const Eigen::Vector3d& a = *axes[k];
    const Eigen::Vector3d moment = r.cross(a);
    for (int i = 0; i < 3; ++i) {
      out.value(k, i) = a(i);
      out.value(k, 3 + i) = R.col(i).dot(moment);
    }
  }
}

void RigidBody3d::integrate_position(const ConstVectorRef& q, const ConstVectorRef& v_theta,
                                     double h, VectorRef q_next) const {
  q_next.head<3>() = q.head<3>() + h * v_theta.head<3>();
  const Eigen::Vector3d rotation = h * v_theta.tail<3>();
  const double angle = rotation.norm();
  Eigen::Quaterniond increment = Eigen::Quaterniond::Identity();
  if (angle > 0.0) increment = Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation / angle));
  const Eigen::Quaterniond next = (orientation(q) * increment).normalized();
  q_next(3) = next.w();
  q_next(4) = next.x();
  q_next(5) = next.y();
  q_next(6) = next.z();
}

void RigidBody3d::position_difference(const ConstVectorRef& q1, const ConstVectorRef& q0, VectorRef d) const {
  d.head<3>() = q1.head<3>() - q0.head<3>();
  const Eigen::AngleAxisd turn(orientation(q0).normalized().conjugate() * orientation(q1).normalized());
  d.tail<3>() = turn.angle() * turn.axis();
}

// q̇ = ½ q ⊗ (0, ω) for the quaternion, with ω in the body frame.
void RigidBody3d::position_rate(const ConstVectorRef& q, const ConstVectorRef& v, VectorRef q_dot) const {
  q_dot.head<3>() = v.head<3>();
  const Eigen::Quaterniond rate = orientation(q) * Eigen::Quaterniond(0.0, v(3), v(4), v(5));
  q_dot(3) = 0.5 * rate.w();
  q_dot(4) = 0.5 * rate.x();
  q_dot(5) = 0.5 * rate.y();
  q_dot(6) = 0.5 * rate.z();
}

void RigidBody3d::add_inertial_force(const ConstVectorRef& v, VectorRef f) const {
  const Eigen::Vector3d omega = v.tail<3>();
  f.tail<3>() -= omega.cross(inertia_.cwiseProduct(omega));
}

int RigidBody3d::velocity_index(const std::string& component) const {
  static const char* names[] = {"x", "y", "z", "rx", "ry", "rz"};
  for (int i = 0; i < 6; ++i)
    if (component == names[i]) return i;
  return -1;
}

}  // namespace csim
