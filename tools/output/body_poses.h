// DIR/bodies.csv (scene key output.bodies: true): every moving rigid body's and point's pose at the
// rows of probes.csv, so that a scene of many bodies needs no probe per body (docs/contract.md).
//
// One row per output time and body, in the World's body order: `t` (s), `body` (its name), then the
// position of its frame's origin (m) and its orientation: in 3D `x,y,z,qw,qx,qy,qz` (a unit quaternion,
// body to world; a point's is the identity), in the plane `x,y,angle` (rad, counter-clockwise from the
// world's axes). Elastic and fixed bodies have no row (elastic bodies go to ParaView).
#pragma once

#include "engine/state.h"
#include "engine/world.h"

#include <sstream>
#include <string>
#include <vector>

namespace csim {

class BodyPoses {
 public:
  explicit BodyPoses(const World& world);
  void add_frame(const World& world, const State& state);  // at state.t
  std::string text() const { return csv_.str(); }
  int bodies() const { return static_cast<int>(moving_.size()); }

 private:
  int dimension_ = 3;
  std::vector<int> moving_;  // the bodies written: neither fixed nor elastic
  std::ostringstream csv_;
};

}  // namespace csim
