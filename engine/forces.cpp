#include "engine/forces.h"

#include "engine/bodies/rigid_body_2d.h"
#include "engine/bodies/rigid_body_3d.h"

namespace csim {

namespace {

ConstVectorRef body_positions(const BodyInstance& b, const Vector& q) {
  return q.segment(b.position_offset, b.body->position_size());
}

bool rotates(const Body& body) {
  return dynamic_cast<const RigidBody2d*>(&body) || dynamic_cast<const RigidBody3d*>(&body);
}

Eigen::Matrix3d projector(const Eigen::Vector3d& direction) {
  if (direction.isZero()) return Eigen::Matrix3d::Identity();
  return direction * direction.transpose();
}

}  // namespace

ForceModel::ForceModel(const World& world) : world_(world), jacobian_(3, world.velocity_size) {
  for (const Spring& s : world.springs) {
    const BodyInstance& a = world.bodies[s.body_a];
    reference_points_a_.push_back(a.body->point_world(a.reference_position, s.point_a));
    if (s.body_b >= 0) {
      const BodyInstance& b = world.bodies[s.body_b];
      reference_points_b_.push_back(b.body->point_world(b.reference_position, s.point_b));
    } else {
      reference_points_b_.push_back(Eigen::Vector3d::Zero());
    }
    const bool offset_a = rotates(*a.body) && !s.point_a.isZero();
    const bool offset_b = s.body_b >= 0 && rotates(*world.bodies[s.body_b].body) && !s.point_b.isZero();
    if (offset_a || offset_b) constant_stiffness_ = false;
  }
  for (const BodyInstance& b : world.bodies) has_elastic_bodies_ = has_elastic_bodies_ || b.body->elastic();
}

void ForceModel::add_body_internal_forces(const Vector& q, Vector& f) const {
  for (const BodyInstance& b : world_.bodies)
    if (b.body->elastic())
      b.body->add_internal_force(body_positions(b, q), f.segment(b.velocity_offset, b.body->velocity_size()));
}

// Only the columns of the (at most two) bodies a spring touches are non-zero in its Jacobian.
void ForceModel::add_spring_stiffness(const Vector& q, Triplets& K) const {
  for (const Spring& s : world_.springs) {
    spring_jacobian(s, q, jacobian_);
    const Eigen::Matrix3d P = projector(s.direction);
    std::vector<int> columns;
    for (int body : {s.body_a, s.body_b}) {
      if (body < 0) continue;
      const BodyInstance& b = world_.bodies[body];
      for (int j = 0; j < b.body->velocity_size(); ++j) columns.push_back(b.velocity_offset + j);
    }
    for (int i : columns)
      for (int j : columns) {
        const double value = s.stiffness * jacobian_.col(i).dot(P * jacobian_.col(j));
        if (value != 0.0) K.emplace_back(i, j, value);
      }
  }
}

void ForceModel::external(const Vector& q, double t, Vector& f) const {
  f.setZero(world_.velocity_size);
  Matrix3X& J = jacobian_;
  for (const BodyInstance& b : world_.bodies) {
    if (b.body->fixed() || world_.gravity.isZero()) continue;
    auto Jb = J.leftCols(b.body->velocity_size());
    b.body->point_jacobian(body_positions(b, q), Eigen::Vector3d::Zero(), Jb);
    f.segment(b.velocity_offset, b.body->velocity_size()) += Jb.transpose() * (b.body->mass() * world_.gravity);
  }
  for (const Load& load : world_.loads) {
    const BodyInstance& b = world_.bodies[load.body];
    auto Jb = J.leftCols(b.body->velocity_size());
    b.body->point_jacobian(body_positions(b, q), load.point, Jb);
    f.segment(b.velocity_offset, b.body->velocity_size()) += Jb.transpose() * (load.multiplier(t) * load.force);
  }
}

Eigen::Vector3d ForceModel::spring_displacement(const Spring& s, const Vector& q) const {
  const std::size_t i = &s - world_.springs.data();
  const BodyInstance& a = world_.bodies[s.body_a];
  Eigen::Vector3d d = a.body->point_world(body_positions(a, q), s.point_a) - reference_points_a_[i];
  if (s.body_b >= 0) {
    const BodyInstance& b = world_.bodies[s.body_b];
    d -= b.body->point_world(body_positions(b, q), s.point_b) - reference_points_b_[i];
  }
  return d;
}

// J maps v to the relative velocity of the two points (ṗ_a − ṗ_b), 3 × velocity_size.
void ForceModel::spring_jacobian(const Spring& s, const Vector& q, Matrix3X& J) const {
  J.setZero();
  const BodyInstance& a = world_.bodies[s.body_a];
  a.body->point_jacobian(body_positions(a, q), s.point_a,
                         J.middleCols(a.velocity_offset, a.body->velocity_size()));
  if (s.body_b >= 0) {
    const BodyInstance& b = world_.bodies[s.body_b];
    Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 6> Jb(3, b.body->velocity_size());
    b.body->point_jacobian(body_positions(b, q), s.point_b, Jb);
    J.middleCols(b.velocity_offset, b.body->velocity_size()) -= Jb;
  }
}

void ForceModel::add_spring_forces(const Vector& q, Vector& f) const {
  for (const Spring& s : world_.springs) {
    const Eigen::Vector3d force_on_a = -s.stiffness * (projector(s.direction) * spring_displacement(s, q));
    spring_jacobian(s, q, jacobian_);
    f.noalias() += jacobian_.transpose() * force_on_a;
  }
}

void ForceModel::spring_stiffness(const Vector& q, Matrix& K) const {
  K.setZero(world_.velocity_size, world_.velocity_size);
  for (const Spring& s : world_.springs) {
    spring_jacobian(s, q, jacobian_);
    K.noalias() += s.stiffness * (jacobian_.transpose() * projector(s.direction) * jacobian_);
  }
}

double ForceModel::elastic_energy(const Vector& q) const {
  double energy = 0.0;
  for (const BodyInstance& b : world_.bodies)
    if (b.body->elastic()) energy += b.body->strain_energy(body_positions(b, q));
  for (const Spring& s : world_.springs)
    energy += 0.5 * s.stiffness * (projector(s.direction) * spring_displacement(s, q)).squaredNorm();
  return energy;
}

}  // namespace csim
