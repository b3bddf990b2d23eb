// A point mass in the plane (x, y) or in space (x, y, z); q = v-coordinates = position (m).
// Shapes attached to it translate with it and never rotate.
#pragma once

#include "engine/bodies/body.h"

namespace csim {

class PointMass final : public Body {
 public:
  PointMass(int dimension, double mass) : dimension_(dimension), mass_(mass) {}

  int position_size() const override { return dimension_; }
  int velocity_size() const override { return dimension_; }
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
  int velocity_index(const std::string& component) const override;

 private:
  int dimension_;
  double mass_;  // kg
};

}  // namespace csim
