#include "tools/output/body_poses.h"

#include "tools/output/csv_text.h"

#include <cmath>
#include <iomanip>

namespace csim {

BodyPoses::BodyPoses(const World& world) : dimension_(world.dimension) {
  for (int i = 0; i < static_cast<int>(world.bodies.size()); ++i) {
    const Body& body = *world.bodies[i].body;
    if (!body.fixed() && !body.elastic()) moving_.push_back(i);
  }
  csv_ << std::setprecision(15) << (dimension_ == 2 ? "t,body,x,y,angle\n" : "t,body,x,y,z,qw,qx,qy,qz\n");
}

void BodyPoses::add_frame(const World& world, const State& state) {
  for (const int i : moving_) {
    const BodyInstance& b = world.bodies[i];
    const Eigen::Isometry3d pose = b.body->pose(b.positions(state.q));
    const Eigen::Vector3d x = pose.translation();
    csv_ << state.t << ',' << csv_field(b.name) << ',' << x.x() << ',' << x.y();
    if (dimension_ == 2) {
      csv_ << ',' << std::atan2(pose.linear()(1, 0), pose.linear()(0, 0)) << '\n';
      continue;
    }
    const Eigen::Quaterniond q(pose.linear());
    csv_ << ',' << x.z() << ',' << q.w() << ',' << q.x() << ',' << q.y() << ',' << q.z() << '\n';
  }
}

}  // namespace csim
