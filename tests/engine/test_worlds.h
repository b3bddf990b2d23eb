// Small worlds built in code for the stepper tests.
#pragma once

#include "engine/bodies/point_mass.h"
#include "engine/state.h"
#include "engine/world.h"

#include <memory>
#include <string>

namespace csim::test {

inline BodyInstance point_mass(const std::string& name, int dimension, double mass,
                               const Eigen::Vector3d& position,
                               const Eigen::Vector3d& velocity = Eigen::Vector3d::Zero()) {
  BodyInstance b;
  b.name = name;
  b.body = std::make_unique<PointMass>(dimension, mass);
  b.reference_position = position.head(dimension);
  b.initial_position = b.reference_position;
  b.initial_velocity = velocity.head(dimension);
  return b;
}

inline State start(const World& world) {
  State s;
  s.q.setZero(world.position_size);
  s.v.setZero(world.velocity_size);
  for (const BodyInstance& b : world.bodies) {
    s.q.segment(b.position_offset, b.body->position_size()) = b.initial_position;
    s.v.segment(b.velocity_offset, b.body->velocity_size()) = b.initial_velocity;
  }
  return s;
}

// A 2 kg mass on an 800 N/m spring to the ground, released 1 cm from rest (ω = 20 rad/s).
inline World oscillator() {
  World world;
  world.dimension = 2;
  world.bodies.push_back(point_mass("mass", 2, 2.0, Eigen::Vector3d::Zero()));
  world.bodies[0].initial_position << 0.01, 0.0;
  Spring spring;
  spring.body_a = 0;
  spring.stiffness = 800.0;
  world.springs.push_back(spring);
  world.finalize_layout();
  return world;
}

// A 1.5 kg point mass in space pushed by (3, 0, −1) N, constrained to x − 2y = 0.01 m (it starts on
// the line, at rest).
inline World constrained_point() {
  World world;
  world.dimension = 3;
  world.bodies.push_back(point_mass("p", 3, 1.5, Eigen::Vector3d::Zero()));
  world.bodies[0].initial_position << 0.01, 0.0, 0.0;
  world.finalize_layout();
  Load load;
  load.body = 0;
  load.force << 3.0, 0.0, -1.0;
  world.loads.push_back(load);
  LinearConstraint c;
  c.terms = {{0, 1.0}, {1, -2.0}};
  c.value = 0.01;
  world.constraints.push_back(c);
  return world;
}

}  // namespace csim::test
