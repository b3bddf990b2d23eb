#include "engine/bodies/point_mass.h"

namespace csim {

void PointMass::add_mass(int offset, Triplets& mass) const {
  for (int i = 0; i < dimension_; ++i) mass.emplace_back(offset + i, offset + i, mass_);
}

Eigen::Isometry3d PointMass::pose(const ConstVectorRef& q) const {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation().head(dimension_) = q;
  return pose;
}

PointJacobian PointMass::point_jacobian(const ConstVectorRef&, const Eigen::Vector3d&) const {
  PointJacobian J;
  for (int i = 0; i < dimension_; ++i) J.add(i, Eigen::Vector3d::Unit(i));
  return J;
}

void PointMass::project_world_point_jacobian(const ConstVectorRef&, const Eigen::Vector3d&,
                                             const Eigen::Vector3d* const* axes, int axis_count,
                                             ProjectedJacobian& out) const {
  out.count = dimension_;
  out.ascending = true;
  for (int j = 0; j < dimension_; ++j) out.index[j] = j;
  for (int k = 0; k < axis_count; ++k)
    for (int j = 0; j < dimension_; ++j) out.value(k, j) = (*axes[k])(j);
}

// A point mass's Jacobian is the same at every point.
void PointMass::project_lever_arm_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& r,
                                           const Eigen::Vector3d* const* axes, int axis_count,
                                           ProjectedJacobian& out) const {
  project_world_point_jacobian(q, r, axes, axis_count, out);
}

void PointMass::integrate_position(const ConstVectorRef& q, const ConstVectorRef& v_theta, double h,
                                   VectorRef q_next) const {
  q_next = q + h * v_theta;
}

int PointMass::velocity_index(const std::string& component) const {
  if (component == "x") return 0;
  if (component == "y") return 1;
  if (component == "z" && dimension_ == 3) return 2;
  return -1;
}

}  // namespace csim
