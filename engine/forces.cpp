#include "engine/forces.h"

#include <array>

#include "engine/bodies/rigid_body_2d.h"
#include "engine/bodies/rigid_body_3d.h"

namespace csim {

namespace {

bool rotates(const Body& body) {
  return dynamic_cast<const RigidBody2d*>(&body) || dynamic_cast<const RigidBody3d*>(&body);
}

Eigen::Matrix3d projector(const Eigen::Vector3d& direction) {
  if (direction.isZero()) return Eigen::Matrix3d::Identity();
  return direction * direction.transpose();
}

}  // namespace

ForceModel::ForceModel(const World& world) : world_(world) {
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
      b.body->add_internal_force(b.positions(q), f.segment(b.velocity_offset, b.body->velocity_size()));
}

namespace {

// The relative velocity of a spring's two points, ṗ_a − ṗ_b, as the Jacobians of its ends, each with
// its body's velocity offset.
struct SpringEnds {
  PointJacobian a, b;
  int offset_a = 0, offset_b = 0;
  bool has_b = false;
};

SpringEnds spring_ends(const World& world, const Spring& s, const Vector& q) {
  SpringEnds ends;
  const BodyInstance& a = world.bodies[s.body_a];
  ends.a = a.body->point_jacobian(a.positions(q), s.point_a);
  ends.offset_a = a.velocity_offset;
  if (s.body_b >= 0) {
    const BodyInstance& b = world.bodies[s.body_b];
    ends.b = b.body->point_jacobian(b.positions(q), s.point_b);
    ends.offset_b = b.velocity_offset;
    ends.has_b = true;
  }
  return ends;
}

// The (global index, column) entries of a spring's Jacobian, at most six per end: a fixed-size list,
// because this runs in every step.
struct Entry {
  int index = 0;
  Eigen::Vector3d column = Eigen::Vector3d::Zero();
};
struct Entries {
  std::array<Entry, 12> entry;
  int count = 0;
  const Entry* begin() const { return entry.data(); }
  const Entry* end() const { return entry.data() + count; }
};
Entries entries_of(const SpringEnds& ends) {
  Entries entries;
  for (int k = 0; k < ends.a.count; ++k) entries.entry[entries.count++] = {ends.offset_a + ends.a.index[k], ends.a.column.col(k)};
  if (ends.has_b)
    for (int k = 0; k < ends.b.count; ++k)
      entries.entry[entries.count++] = {ends.offset_b + ends.b.index[k], -ends.b.column.col(k)};
  return entries;
}

}  // namespace

void ForceModel::add_spring_stiffness(const Vector& q, Triplets& K) const {
  for (const Spring& s : world_.springs) {
    const Eigen::Matrix3d P = projector(s.direction);
    const Entries entries = entries_of(spring_ends(world_, s, q));
    for (const Entry& i : entries)
      for (const Entry& j : entries) {
        const double value = s.stiffness * i.column.dot(P * j.column);
        if (value != 0.0) K.emplace_back(i.index, j.index, value);
      }
  }
}

void ForceModel::external(const Vector& q, double t, Vector& f) const {
  f.setZero(world_.velocity_size);
  if (!world_.gravity.isZero())
    for (const BodyInstance& b : world_.bodies)
      if (!b.body->fixed())
        b.body->add_weight(b.positions(q), world_.gravity, f.segment(b.velocity_offset, b.body->velocity_size()));
  for (const Load& load : world_.loads) {
    const BodyInstance& b = world_.bodies[load.body];
    const double multiplier = load.multiplier(t);
    if (load.nodal_forces.size() > 0) {  // a distributed load, already in the body's coordinates
      f.segment(b.velocity_offset, b.body->velocity_size()) += multiplier * load.nodal_forces;
      continue;
    }
    const PointJacobian J = b.body->point_jacobian(b.positions(q), load.point);
    for (int k = 0; k < J.count; ++k)
      f(b.velocity_offset + J.index[k]) += J.column.col(k).dot(multiplier * load.force);
  }
}

Eigen::Vector3d ForceModel::spring_displacement(const Spring& s, const Vector& q) const {
  const std::size_t i = &s - world_.springs.data();
  const BodyInstance& a = world_.bodies[s.body_a];
  Eigen::Vector3d d = a.body->point_world(a.positions(q), s.point_a) - reference_points_a_[i];
  if (s.body_b >= 0) {
    const BodyInstance& b = world_.bodies[s.body_b];
    d -= b.body->point_world(b.positions(q), s.point_b) - reference_points_b_[i];
  }
  return d;
}

void ForceModel::add_spring_forces(const Vector& q, Vector& f) const {
  for (const Spring& s : world_.springs) {
    const Eigen::Vector3d force_on_a = -s.stiffness * (projector(s.direction) * spring_displacement(s, q));
    for (const Entry& e : entries_of(spring_ends(world_, s, q))) f(e.index) += e.column.dot(force_on_a);
  }
}

void ForceModel::spring_stiffness(const Vector& q, Matrix& K) const {
  K.setZero(world_.velocity_size, world_.velocity_size);
  for (const Spring& s : world_.springs) {
    const Eigen::Matrix3d P = projector(s.direction);
    const Entries entries = entries_of(spring_ends(world_, s, q));
    for (const Entry& i : entries)
      for (const Entry& j : entries) K(i.index, j.index) += s.stiffness * i.column.dot(P * j.column);
  }
}

double ForceModel::elastic_energy(const Vector& q) const {
  double energy = 0.0;
  for (const BodyInstance& b : world_.bodies)
    if (b.body->elastic()) energy += b.body->strain_energy(b.positions(q));
  for (const Spring& s : world_.springs)
    energy += 0.5 * s.stiffness * (projector(s.direction) * spring_displacement(s, q)).squaredNorm();
  return energy;
}

}  // namespace csim
