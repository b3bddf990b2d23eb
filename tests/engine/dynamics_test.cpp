// Springs and loads as generalized forces: directions, signs, torques, energies, time functions.
#include "engine/bodies/point_mass.h"
#include "engine/bodies/rigid_body_2d.h"
#include "engine/dynamics.h"

#include <gtest/gtest.h>

namespace csim {
namespace {

BodyInstance make(const std::string& name, std::unique_ptr<Body> body, const Vector& q_ref) {
  BodyInstance b;
  b.name = name;
  b.body = std::move(body);
  b.reference_position = q_ref;
  b.initial_position = q_ref;
  b.initial_velocity.setZero(b.body->velocity_size());
  return b;
}

TEST(Forces, SpringBetweenTwoBodiesActsEquallyAndOppositely) {
  World world;
  world.dimension = 2;
  world.bodies.push_back(make("a", std::make_unique<PointMass>(2, 1.0), Eigen::Vector2d(0, 0)));
  world.bodies.push_back(make("b", std::make_unique<PointMass>(2, 1.0), Eigen::Vector2d(1, 0)));
  world.finalize_layout();
  Spring s;
  s.body_a = 0;
  s.body_b = 1;
  s.stiffness = 100.0;
  world.springs.push_back(s);
  const Dynamics forces(world);
  Vector q(4);
  q << 0.01, 0.02, 1.0, -0.01;  // relative displacement d = u_a − u_b = (0.01, 0.03)
  Vector f = Vector::Zero(4);
  forces.add_spring_forces(q, f);
  EXPECT_NEAR(f(0), -1.0, 1e-13);
  EXPECT_NEAR(f(1), -3.0, 1e-13);
  EXPECT_NEAR(f(2), 1.0, 1e-13);
  EXPECT_NEAR(f(3), 3.0, 1e-13);
  EXPECT_NEAR(forces.elastic_energy(q), 0.5 * 100.0 * (1e-4 + 9e-4), 1e-15);
  EXPECT_TRUE(forces.constant_stiffness());
  Matrix K;
  forces.spring_stiffness(q, K);
  EXPECT_NEAR((K * (q - Vector((Eigen::Vector4d() << 0, 0, 1, 0).finished())) + f).norm(), 0.0, 1e-12);
}

TEST(Forces, SpringAlongOneDirectionIgnoresTheOthers) {
  World world;
  world.dimension = 2;
  world.bodies.push_back(make("a", std::make_unique<PointMass>(2, 1.0), Eigen::Vector2d(0, 0)));
  world.finalize_layout();
  Spring s;
  s.body_a = 0;
  s.stiffness = 10.0;
  s.direction = Eigen::Vector3d::UnitX();
  world.springs.push_back(s);
  const Dynamics forces(world);
  Vector f = Vector::Zero(2);
  forces.add_spring_forces(Eigen::Vector2d(0.5, 7.0), f);
  EXPECT_DOUBLE_EQ(f(0), -5.0);
  EXPECT_DOUBLE_EQ(f(1), 0.0);
}

TEST(Forces, OffsetSpringOnARigidBodyGivesATorque) {
  World world;
  world.dimension = 2;
  world.bodies.push_back(make("r", std::make_unique<RigidBody2d>(1.0, 0.1), Eigen::Vector3d(0, 0, 0)));
  world.finalize_layout();
  Spring s;
  s.body_a = 0;
  s.point_a = Eigen::Vector3d(0, 0.5, 0);  // half a metre above the centre
  s.stiffness = 10.0;
  s.direction = Eigen::Vector3d::UnitX();
  world.springs.push_back(s);
  const Dynamics forces(world);
  EXPECT_FALSE(forces.constant_stiffness());
  Vector f = Vector::Zero(3);
  forces.add_spring_forces(Eigen::Vector3d(0.1, 0, 0), f);  // translated 0.1 along x
  EXPECT_DOUBLE_EQ(f(0), -1.0);
  EXPECT_DOUBLE_EQ(f(2), 0.5);  // r × F = (0, 0.5) × (−1, 0) = +0.5 about z
}

TEST(Forces, LoadsFollowTheirTimeFunctionAndGravityActsOnTheMass) {
  World world;
  world.dimension = 2;
  world.gravity = Eigen::Vector3d(0, -10, 0);
  world.bodies.push_back(make("p", std::make_unique<PointMass>(2, 3.0), Eigen::Vector2d(0, 0)));
  world.finalize_layout();
  Load ramp;
  ramp.body = 0;
  ramp.force = Eigen::Vector3d(4, 0, 0);
  ramp.multiplier.ramp_time = 2.0;
  Load table;
  table.body = 0;
  table.force = Eigen::Vector3d(0, 1, 0);
  table.multiplier.table = {{0.0, 0.0}, {1.0, 2.0}, {3.0, -2.0}};
  world.loads = {ramp, table};
  const Dynamics forces(world);
  Vector f;
  forces.external(Eigen::Vector2d::Zero(), 0.5, f);
  EXPECT_DOUBLE_EQ(f(0), 1.0);           // 4 · 0.5/2
  EXPECT_DOUBLE_EQ(f(1), -30.0 + 1.0);   // m g + table(0.5) = 1
  forces.external(Eigen::Vector2d::Zero(), 2.5, f);
  EXPECT_DOUBLE_EQ(f(0), 4.0);
  EXPECT_DOUBLE_EQ(f(1), -30.0 - 1.0);   // table(2.5) = −1
  forces.external(Eigen::Vector2d::Zero(), 10.0, f);
  EXPECT_DOUBLE_EQ(f(1), -30.0 - 2.0);   // held beyond the last point
}

}  // namespace
}  // namespace csim
