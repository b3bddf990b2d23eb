// A rigid body in the plane: q = v-coordinates = (x, y, φ) — centre of mass (m) and rotation about
// e_z (rad, counter-clockwise). Mass matrix diag(m, m, I) with I the moment of inertia about the
// centre of mass (kg·m²).
#pragma once

#include "engine/bodies/body.h"

namespace csim {

class RigidBody2d final : public Body {
 public:
  RigidBody2d(double mass, double inertia) : mass_(mass), inertia_(inertia) {}

  int position_size() const override { return 3; }
  int translation_coordinates() const override { return 2; }
  int velocity_size() const override { return 3; }
  double mass() const override { return mass_; }
  void add_mass(int offset, Triplets& mass) const override;
  Eigen::Isometry3d pose(const ConstVectorRef& q) const override;
  Eigen::Vector3d point_world(const ConstVectorRef& q, const Eigen::Vector3d& local) const override;
  PointJacobian point_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& local) const override;
  Eigen::Vector3d point_kinematics(const ConstVectorRef& q, const Eigen::Vector3d& local,
                                   PointJacobian& J) const override;
  void project_world_point_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& x, const Eigen::Vector3d* const* axes,
                                    int axis_count, ProjectedJacobian& out) const override;
  void project_lever_arm_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& r, const Eigen::Vector3d* const* axes,
                                    int axis_count, ProjectedJacobian& out) const override;
  void integrate_position(const ConstVectorRef& q, const ConstVectorRef& v_theta, double h,
                          VectorRef q_next) const override;
  int velocity_index(const std::string& component) const override;
  std::vector<std::pair<int, Eigen::Vector3d>> rotation_axes() const override {
    return {{2, Eigen::Vector3d::UnitZ()}};
  }

 private:
  void cos_sin(double angle, double& c, double& s) const;

  double mass_;     // kg
  double inertia_;  // kg·m²
  // cos and sin of the last angle asked (rad), a pure function's memo: one thread per body, as the run.
  mutable double cached_angle_ = 0.0, cached_cos_ = 1.0, cached_sin_ = 0.0;
};

}  // namespace csim
