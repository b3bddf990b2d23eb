// Sleeping bodies (engine/steppers/sleeping_islands.h) in Moreau–Jean runs: a body at rest falls asleep
// and still carries its weight in its contacts; a body dropped on an asleep one wakes it before the
// contact problem is formed, and the run then agrees with the run that never slept; a block held by
// static friction sleeps where a sliding one never does (Coulomb's limit, closed form); a loaded body
// never sleeps; the energy balance closes with what sleeping removed.
#include "engine/steppers/moreau_jean.h"
#include "tests/engine/test_worlds.h"
#include "tools/scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <unistd.h>

namespace csim {
namespace {

constexpr double kG = 9.81, kStep = 1e-3;

std::unique_ptr<Scene> scene_of(const std::string& text, const std::string& name) {
  const std::string file = ::testing::TempDir() + "sleeping_" + name + "_" + std::to_string(getpid()) + ".yaml";
  std::ofstream(file) << text;
  auto scene = load_scene(file, {});
  std::remove(file.c_str());
  return scene;
}

struct Stepping {
  Stepping(const World& world, const MoreauJeanParameters& parameters) : stepper(world, parameters), state(test::start(world)) {
    stepper.initialize(state);
  }
  void until(double t) {
    while (state.t < t - 0.5 * kStep) stepper.step(state);
  }
  MoreauJean stepper;
  State state;
};

MoreauJeanParameters sleeping(const Scene& scene, double speed, double time) {
  MoreauJeanParameters p = moreau_jean_parameters(scene.run);
  p.sleep.speed = speed;
  p.sleep.time = time;
  return p;
}

// The normal force (N) the listed contacts exert, their impulses over the step.
double normal_force(const State& s) {
  double sum = 0.0;
  for (const ActiveContact& c : s.contacts) sum += c.impulse(0) / kStep;
  return sum;
}

// Unit cubes of 1 kg on a floor under gravity g = 9.81 (x, 0, z components given), μ as given.
std::string cubes(const std::string& gravity, double mu, const std::string& bodies, const std::string& extra = "",
                  bool stacked = false) {
  return "dimension: 3\ngravity: " + gravity + R"(
bodies:
)" + bodies + R"(
  floor: {type: fixed, shapes: {top: {type: halfspace, normal: [0, 0, 1], offset: 0}}}
contacts:
  on_floor: {between: [floor, cubes], mu: )" + std::to_string(mu) + R"(}
)" + (stacked ? "  stacked: {between: [cubes, cubes], mu: " + std::to_string(mu) + "}\n" : "") + R"(time: {end: 1, step: 1e-3}
contact_solver: {tolerance: 1e-10, max_iterations: 20000}
)" + extra;
}

const char* kOneCube =
    "  a: {type: rigid, mass: 1, position: [0, 0, 0.5], group: cubes, shapes: {c: {type: box, size: [1, 1, 1]}}}\n";

TEST(Sleeping, ABlockAtRestFallsAsleepAndItsContactsStillCarryItsWeight) {
  const auto scene = scene_of(cubes("[0, 0, -9.81]", 0.5, kOneCube), "rest");
  Stepping run(scene->world, sleeping(*scene, 1e-3, 0.05));
  run.until(0.1);
  ASSERT_EQ(run.stepper.sleeping().asleep_count(), 1);
  const long solves = run.state.counters.solves;
  const Vector q = run.state.q;
  run.until(0.3);
  EXPECT_EQ(run.state.counters.solves, solves);  // no contact problem while asleep
  EXPECT_EQ(run.state.q, q);                      // held
  EXPECT_EQ(run.state.v.norm(), 0.0);
  ASSERT_EQ(run.state.contacts.size(), 4u);  // the box's four corners, kept
  EXPECT_NEAR(normal_force(run.state), kG, 1e-8 * kG);
  EXPECT_LE(std::abs(run.state.energy.residual()), 1e-12);
  EXPECT_GE(run.state.energy.sleep_dissipation, 0.0);
}

// Sphere a rests on the floor (asleep from 0.05 s); sphere b, released 0.3 m above it, strikes it at
// 0.247 s, and a wakes before that step's contact problem is formed. Compared with the same run without
// sleeping: the answer must not depend on whether a slept (it was at rest to round-off in both).
TEST(Sleeping, ABodyDroppedOnAnAsleepOneWakesItAndTheRunAgreesWithTheRunThatNeverSlept) {
  const std::string bodies =
      "  a: {type: rigid, mass: 1, position: [0, 0, 0.1], group: cubes, shapes: {s: {type: sphere, radius: 0.1}}}\n"
      "  b: {type: rigid, mass: 1, position: [0, 0, 0.6], group: cubes, shapes: {s: {type: sphere, radius: 0.1}}}\n";
  const auto scene = scene_of(cubes("[0, 0, -9.81]", 0.5, bodies, "", true), "wake");
  Stepping asleep(scene->world, sleeping(*scene, 1e-3, 0.05));
  Stepping awake(scene->world, moreau_jean_parameters(scene->run));
  asleep.until(0.15);
  EXPECT_EQ(asleep.stepper.sleeping().asleep_count(), 1);  // a (b is falling)
  asleep.until(0.6);
  awake.until(0.6);
  EXPECT_GE(asleep.stepper.sleeping().islands_woken(), 1);
  // b falls 0.3 m in √(0.6/g) = 0.247 s; by 0.6 s both rest, a on the floor, b on a.
  const int za = scene->world.bodies[0].position_offset + 2, zb = scene->world.bodies[1].position_offset + 2;
  EXPECT_NEAR(asleep.state.q(za), awake.state.q(za), 1e-9);
  EXPECT_NEAR(asleep.state.q(zb), awake.state.q(zb), 1e-9);
  // Resting on a, to the overlap the θ-scheme leaves at an impact, at most h (1 − θ) · √(2 g 0.3 m).
  EXPECT_NEAR(asleep.state.q(zb), 0.3, 0.5 * kStep * std::sqrt(2 * kG * 0.3));
  EXPECT_NEAR(asleep.state.counters.deepest_penetration, awake.state.counters.deepest_penetration, 1e-9);
  // The floor carries both spheres (sum of its contact with a and a–b's, each counted on its normal).
  asleep.until(0.9);
  EXPECT_EQ(asleep.stepper.sleeping().asleep_count(), 2);
  double floor = 0.0;
  for (const ActiveContact& c : asleep.state.contacts)
    if (scene->world.bodies[c.body_a].body->fixed() || scene->world.bodies[c.body_b].body->fixed())
      floor += c.impulse(0) / kStep;
  EXPECT_NEAR(floor, 2 * kG, 1e-6 * kG);
  EXPECT_LE(std::abs(asleep.state.energy.residual()), 1e-10);
}

// Gravity tilted by α from the floor's normal is a block on an incline of angle α. At tan α = 0.99 μ
// static friction holds it (Coulomb: |r_t| ≤ μ r_n) and it falls asleep; at tan α = 1.01 μ it slides
// with a = g (sin α − μ cos α) and never sleeps.
TEST(Sleeping, StaticFrictionSleepsAndSlidingNever) {
  const double mu = 0.5;
  for (const double ratio : {0.99, 1.01}) {
    const double alpha = std::atan(ratio * mu);
    char gravity[96];
    std::snprintf(gravity, sizeof gravity, "[%.17g, 0, %.17g]", kG * std::sin(alpha), -kG * std::cos(alpha));
    const auto scene = scene_of(cubes(gravity, mu, kOneCube), "incline");
    Stepping run(scene->world, sleeping(*scene, 1e-3, 0.05));
    run.until(0.5);
    if (ratio < 1.0) {
      EXPECT_EQ(run.stepper.sleeping().asleep_count(), 1) << ratio;
      EXPECT_LE(std::abs(run.state.q(0)), 1e-12);  // stuck (the solver's tolerance), then held
      const Vector q = run.state.q;
      run.until(1.0);
      EXPECT_EQ(run.state.q, q);
    } else {
      EXPECT_EQ(run.stepper.sleeping().asleep_count(), 0) << ratio;
      const double a = kG * (std::sin(alpha) - mu * std::cos(alpha));
      EXPECT_NEAR(run.state.v(0), a * 0.5, 1e-6 * a) << ratio;
    }
  }
}

TEST(Sleeping, ALoadedBodyNeverSleeps) {
  const auto scene = scene_of(
      cubes("[0, 0, -9.81]", 0.5, kOneCube, "loads: {press: {body: a, force: [0, 0, -1]}}\n"),
      "loaded");
  Stepping run(scene->world, sleeping(*scene, 1e-3, 0.05));
  run.until(0.2);
  EXPECT_EQ(run.stepper.sleeping().asleep_count(), 0);
  EXPECT_NEAR(normal_force(run.state), kG + 1.0, 1e-8 * kG);
}

}  // namespace
}  // namespace csim
