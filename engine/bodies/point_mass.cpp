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

void PointMass::point_jacobian(const ConstVectorRef&, const Eigen::Vector3d&,
                               Eigen::Ref<Matrix3X> J) const {
  J.setZero();
  for (int i = 0; i < dimension_; ++i) J(i, i) = 1.0;
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
