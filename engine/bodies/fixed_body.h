// A body that never moves (grounds, walls): no coordinates, a constant pose.
#pragma once

#include "engine/bodies/body.h"

namespace csim {

class FixedBody final : public Body {
 public:
  explicit FixedBody(const Eigen::Isometry3d& pose) : pose_(pose) {}

  int position_size() const override { return 0; }
  int velocity_size() const override { return 0; }
  double mass() const override { return 0.0; }
  void add_mass(int, Triplets&) const override {}
  Eigen::Isometry3d pose(const ConstVectorRef&) const override { return pose_; }
  PointJacobian point_jacobian(const ConstVectorRef&, const Eigen::Vector3d&) const override { return {}; }
  void integrate_position(const ConstVectorRef&, const ConstVectorRef&, double, VectorRef) const override {}
  int velocity_index(const std::string&) const override { return -1; }

 private:
  Eigen::Isometry3d pose_;
};

}  // namespace csim
