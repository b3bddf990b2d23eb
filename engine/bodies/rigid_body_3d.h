// A rigid body in space.
//   q = (x, y, z, q_w, q_x, q_y, q_z): centre of mass (m) and unit quaternion (body → world);
//   v = (v_x, v_y, v_z, ω_x, ω_y, ω_z): centre-of-mass velocity in the world frame (m/s) and angular
//       velocity in the body frame (rad/s), so that the mass matrix diag(m, m, m, I₁, I₂, I₃) is
//       constant (principal inertia, kg·m²); the gyroscopic term −ω × Iω is an inertial force.
// The rotation is advanced on the group: R_{k+1} = R_k exp(h ω_θ).
#pragma once

#include "engine/bodies/body.h"

namespace csim {

class RigidBody3d final : public Body {
 public:
  RigidBody3d(double mass, const Eigen::Vector3d& principal_inertia)
      : mass_(mass), inertia_(principal_inertia) {}

  int position_size() const override { return 7; }
  int translation_coordinates() const override { return 3; }
  int velocity_size() const override { return 6; }
  double mass() const override { return mass_; }
  void add_mass(int offset, Triplets& mass) const override;
  Eigen::Isometry3d pose(const ConstVectorRef& q) const override;
  PointJacobian point_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& local) const override;
  void project_world_point_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& x, const Eigen::Vector3d* const* axes,
                                    int axis_count, ProjectedJacobian& out) const override;
  void project_lever_arm_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& r, const Eigen::Vector3d* const* axes,
                                    int axis_count, ProjectedJacobian& out) const override;
  void integrate_position(const ConstVectorRef& q, const ConstVectorRef& v_theta, double h,
                          VectorRef q_next) const override;
  int coordinate_of(int c) const override { return c < 3 ? c : -1; }
  // The translation, and the rotation vector of R0⁻¹ R1 (body frame, rad).
  void position_difference(const ConstVectorRef& q1, const ConstVectorRef& q0, VectorRef d) const override;
  void position_rate(const ConstVectorRef& q, const ConstVectorRef& v, VectorRef q_dot) const override;
  void add_inertial_force(const ConstVectorRef& v, VectorRef f) const override;
  bool has_inertial_force() const override { return true; }
  bool position_rate_is_velocity() const override { return false; }
  int velocity_index(const std::string& component) const override;
  std::vector<std::pair<int, Eigen::Vector3d>> rotation_axes() const override {
    return {{3, Eigen::Vector3d::UnitX()}, {4, Eigen::Vector3d::UnitY()}, {5, Eigen::Vector3d::UnitZ()}};
  }

 private:
  double mass_;               // kg
  Eigen::Vector3d inertia_;   // kg·m², principal, body frame
  // A step asks for the same orientation's rotation a dozen times (poses, Jacobians of contacts and
  // loads): it is kept for the last quaternion asked, compared bit for bit.
  const Eigen::Matrix3d& rotation(const ConstVectorRef& q) const;
  mutable bool rotation_cached_ = false;
  mutable double cached_quaternion_[4];
  mutable Eigen::Matrix3d cached_rotation_;
};

}  // namespace csim
