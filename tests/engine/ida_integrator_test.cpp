// The IDA integrator on worlds built in code: accuracy against closed forms, energy bookkeeping,
// constraint elimination, the KLU path against the dense one, creep of regularized friction, and a
// failure that becomes a RunError instead of an abort.
#include "engine/bodies/fixed_body.h"
#include "engine/bodies/point_mass.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"
#include "engine/steppers/ida_integrator.h"
#include "tests/engine/test_worlds.h"

#include <gtest/gtest.h>

#include <cmath>

namespace csim {
namespace {

using test::constrained_point;
using test::oscillator;
using test::point_mass;
using test::start;

IdaParameters tight(double sample_step) {
  IdaParameters p;
  p.sample_step = sample_step;
  p.rtol = 1e-10;
  p.atol = 1e-12;
  return p;
}

TEST(IdaIntegrator, FreeOscillatorMatchesTheClosedFormAndKeepsItsEnergy) {
  const World world = oscillator();
  IdaIntegrator ida(world, tight(1e-2));
  State s = start(world);
  ida.initialize(s);
  const double e0 = s.energy.kinetic + s.energy.elastic;
  for (int k = 0; k < 200; ++k) {
    ida.step(s);
    ASSERT_NEAR(s.q(0), 0.01 * std::cos(20.0 * s.t), 1e-9) << "t = " << s.t;
  }
  EXPECT_NEAR(s.energy.kinetic + s.energy.elastic, e0, 1e-7 * e0);
  EXPECT_EQ(s.ida.linear_solver, "dense");
  EXPECT_GT(s.ida.steps, 0);
  EXPECT_GT(s.ida.residual_evaluations, s.ida.steps);
}

TEST(IdaIntegrator, LinearConstraintsAreEliminatedExactly) {
  const World world = constrained_point();
  IdaIntegrator ida(world, tight(1e-2));
  State s = start(world);
  ida.initialize(s);
  for (int k = 0; k < 300; ++k) {
    ida.step(s);
    ASSERT_NEAR(s.q(0) - 2.0 * s.q(1), 0.01, 1e-12);
  }
  const Eigen::Vector3d e = Eigen::Vector3d(2, 1, 0).normalized();
  EXPECT_NEAR((s.q.head<3>() - Eigen::Vector3d(0.01, 0, 0)).dot(e), 0.5 * 3.0 * e.x() / 1.5 * s.t * s.t, 1e-8);
  EXPECT_NEAR(s.energy.kinetic, s.energy.work_of_loads, 1e-8 * s.energy.kinetic);
}

TEST(IdaIntegrator, InitialVelocityViolatingAConstraintIsAnError) {
  World world = oscillator();
  world.bodies[0].initial_velocity << 1.0, 0.0;
  LinearConstraint c;
  c.terms = {{0, 1.0}};
  world.constraints.push_back(c);
  IdaIntegrator ida(world, tight(1e-2));
  State s = start(world);
  EXPECT_THROW(ida.initialize(s), RunError);
}

// 60 masses in a chain of springs (242 unknowns): the automatic choice is KLU with our sparse
// finite-difference Jacobian, and it agrees with the dense solver.
World chain() {
  World world;
  world.dimension = 2;
  for (int i = 0; i < 60; ++i)
    world.bodies.push_back(point_mass("m" + std::to_string(i), 2, 1.0, Eigen::Vector3d(i, 0, 0)));
  world.bodies[59].initial_position << 59.05, 0.02;
  world.finalize_layout();
  for (int i = 0; i < 60; ++i) {
    Spring s;
    s.body_a = i;
    s.body_b = i == 0 ? -1 : i - 1;
    s.stiffness = 100.0;
    world.springs.push_back(s);
  }
  return world;
}

TEST(IdaIntegrator, SparseKluPathAgreesWithTheDenseOne) {
  const World world = chain();
  IdaParameters p = tight(0.05);
  p.rtol = 1e-9;
  p.atol = 1e-11;
  IdaIntegrator sparse(world, p);
  p.linear_solver = "dense";
  IdaIntegrator dense(world, p);
  State a = start(world), b = start(world);
  sparse.initialize(a);
  dense.initialize(b);
  EXPECT_EQ(a.ida.linear_solver, "klu");
  EXPECT_EQ(b.ida.linear_solver, "dense");
  for (int k = 0; k < 20; ++k) {
    sparse.step(a);
    dense.step(b);
  }
  EXPECT_LT((a.q - b.q).norm(), 1e-7);
  EXPECT_GT(a.ida.jacobian_evaluations, 0);
}

// A 1 kg disk of radius 0.1 m, its centre at `height` (m), above a fixed plane y = 0, under g = 10 m/s².
World disk_on_ground(double height) {
  World world;
  world.dimension = 2;
  world.gravity << 0, -10, 0;
  world.bodies.push_back(point_mass("disk", 2, 1.0, Eigen::Vector3d(0, height, 0)));
  world.bodies[0].shapes.push_back(ShapeInstance{"disk", Sphere{0.1}, Eigen::Isometry3d::Identity()});
  world.bodies[0].body->bounding_radius = 0.1;
  BodyInstance ground;
  ground.name = "ground";
  ground.body = std::make_unique<FixedBody>(Eigen::Isometry3d::Identity());
  ground.shapes.push_back(ShapeInstance{"top", Halfspace{Eigen::Vector3d::UnitY(), 0.0}, Eigen::Isometry3d::Identity()});
  world.bodies.push_back(std::move(ground));
  world.finalize_layout();
  return world;
}

TEST(IdaIntegrator, RegularizedFrictionCreepsAtTheVelocityItsLawPredicts) {
  // A point mass on a plane pushed by 0.5 μ m g: true Coulomb friction holds it; the regularized law
  // lets it creep at ε ρ / √(1 − ρ²) with ρ = 0.5.
  World world = disk_on_ground(0.1);
  Load push;
  push.body = 0;
  push.force << 0.5 * 0.4 * 10.0, 0, 0;
  world.loads.push_back(push);
  ContactLaw law;
  law.body_a = 0;
  law.body_b = 1;
  law.mu.setConstant(0.4);
  world.contact_laws.push_back(law);
  IdaParameters p = tight(1e-2);
  p.epsilon = 1e-4;
  IdaIntegrator ida(world, p);
  State s = start(world);
  ida.initialize(s);
  for (int k = 0; k < 100; ++k) ida.step(s);
  EXPECT_NEAR(s.v(0), 1e-4 * 0.5 / std::sqrt(0.75), 1e-3 * 1e-4);
  // Normal force m g from the penalty, with the static penetration m g / k.
  EXPECT_NEAR(s.q(1) - 0.1, -10.0 / (1e8 * 1.0), 1e-10);
}

TEST(IdaIntegrator, ExhaustedStepBudgetIsARunErrorWithTheTime) {
  const World world = oscillator();
  IdaParameters p = tight(0.1);
  p.max_steps = 5;
  IdaIntegrator ida(world, p);
  State s = start(world);
  ida.initialize(s);
  try {
    for (int k = 0; k < 100; ++k) ida.step(s);
    FAIL() << "expected a RunError";
  } catch (const RunError& e) {
    EXPECT_GT(e.time, 0.0);
    EXPECT_NE(std::string(e.what()).find("max_steps"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace csim

namespace csim {
namespace {

// The event-driven mode is the reference of lumped scenes without a closed form: on SDNV104 it must
// reproduce the exact stick-slip solution to 1e-8 relative at tolerance 1e-10.
TEST(IdaEvents, Sdnv104ExtremaAndTimesToOneInHundredMillion) {
  for (const char* ramp : {"parameters.ramp_time=0", "parameters.ramp_time=0.07"}) {
    const auto scene = load_scene(CSIM_SOURCE_DIR "/scenes/sdnv104-rigid/scene.yaml",
                                  {"integrator.type=ida-events", "integrator.rtol=1e-10", "integrator.atol=1e-10", ramp});
    const RunReport report = run_scene(*scene, {});
    int measured = 0;
    for (const CheckResult& c : report.checks) {
      if (c.kind != "analytical" || c.skipped) continue;
      ASSERT_TRUE(c.note.empty()) << c.name << ": " << c.note;
      EXPECT_LE(std::abs(c.error), 1e-8 * std::abs(c.reference)) << ramp << " " << c.name;
      ++measured;
    }
    EXPECT_EQ(measured, 11);  // x1..x5, t1..t5, rest
  }
}

TEST(IdaEvents, StickJustBelowTheThresholdDoesNotMove) {
  const auto scene = load_scene(CSIM_SOURCE_DIR "/scenes/incline/scene.yaml",
                                {"integrator.type=ida-events", "parameters.mu=0.3640702"});
  const RunReport report = run_scene(*scene, {});
  EXPECT_TRUE(report.passed());
  for (const CheckResult& c : report.checks)
    if (c.probe == "slide") {
      EXPECT_LE(std::abs(c.value), 1e-12) << c.name;
    }
}

TEST(IdaEvents, ContactThatIsOpenAtTheStartIsRefusedClearly) {
  const auto scene = load_scene(CSIM_SOURCE_DIR "/scenes/bouncing-ball/scene.yaml", {"integrator.type=ida-events"});
  try {
    run_scene(*scene, {});
    FAIL() << "expected a refusal before the first step";
  } catch (const std::invalid_argument& e) {  // make_stepper: what the stepper cannot run
    EXPECT_NE(std::string(e.what()).find("closed at t = 0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("use ida or moreau-jean"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace csim

namespace csim {
namespace {

// Regularized IDA on SDNV104: the extrema carry the regularization's error (the penalty delays the
// start, the creep replaces the final stop), bounded here by what the header documents.
TEST(IdaIntegrator, Sdnv104WithinTheRegularizationErrorAndNoExactStop) {
  const auto scene = load_scene(CSIM_SOURCE_DIR "/scenes/sdnv104-rigid/scene.yaml",
                                {"integrator.type=ida", "integrator.rtol=1e-8", "integrator.atol=1e-8"});
  const RunReport report = run_scene(*scene, {});
  for (const CheckResult& c : report.checks) {
    if (c.name == "x5" || c.name == "t5") {
      // A regularized law creeps at the last stop instead of sticking: no fifth extremum.
      EXPECT_FALSE(c.note.empty()) << c.name;
      continue;
    }
    if (c.kind != "analytical" || c.skipped) continue;
    EXPECT_TRUE(c.note.empty()) << c.name << ": " << c.note;
    EXPECT_LE(std::abs(c.error), 1e-4 * std::abs(c.reference)) << c.name;
  }
}

TEST(IdaIntegrator, PenaltyEnergyIsElasticAndTheBalanceCloses) {
  // A disk dropped 1 cm on a plane settles on its penalty spring (damped by the restitution e = 0.5):
  // at rest the spring holds ½ k g² = (m g)² / (2k) of elastic energy, which must not be booked as
  // dissipation, and the balance closes to IDA's tolerance.
  World world = disk_on_ground(0.11);
  ContactLaw law;
  law.body_a = 0;
  law.body_b = 1;
  law.restitution = 0.5;
  world.contact_laws.push_back(law);
  IdaParameters p = tight(0.01);
  p.penalty_stiffness = 1e5;  // N/m: a 1e-4 m sink under m g = 10 N
  IdaIntegrator ida(world, p);
  State s = start(world);
  ida.initialize(s);
  while (s.t < 2.0 - 1e-9) ida.step(s);
  const double k = 1e5, weight = 10.0;
  EXPECT_NEAR(s.q(1), 0.1 - weight / k, 1e-7);      // resting on the spring
  EXPECT_NEAR(s.energy.elastic, weight * weight / (2 * k), 1e-3 * weight * weight / (2 * k));
  const double drop = weight * 0.01;                 // J, the energy the drop released
  EXPECT_GT(s.energy.contact_dissipation, 0.9 * drop);  // the dashpot took it, not the spring
  EXPECT_LT(std::abs(s.energy.residual()), 1e-6 * drop);
}

// Issue 28's targets on the elastic bodies, through the scene files and the run loop.
State run_to_end(const Scene& scene) {
  RunOptions quiet;
  return run_scene(scene, quiet).state;
}

TEST(IdaOnElasticBodies, FreeVibrationKeepsItsEnergyToTheTolerance) {
  // The bar's stiffness must be in IDA's forces: without it the energy grew 2000-fold.
  const auto scene = load_scene(CSIM_SOURCE_DIR "/scenes/fe-free-vibration/scene.yaml",
                                {"integrator.type=ida", "integrator.rtol=1e-8", "integrator.atol=1e-10"});
  const State s = run_to_end(*scene);
  const double initial = s.energy.initial_kinetic + s.energy.initial_elastic;
  EXPECT_GT(s.energy.elastic, 0.1 * initial);  // the bar is really deformed
  EXPECT_NEAR(s.energy.kinetic + s.energy.elastic, initial, 1e-4 * initial);
  EXPECT_EQ(s.ida.linear_solver, "klu");
  EXPECT_EQ(s.ida.symbolic_analyses, 1);  // no contact: one pattern
}

TEST(IdaOnElasticBodies, DampedDriftAgreesWithMoreauJean) {
  // Rayleigh damping in IDA's forces and in its energy balance (the damping dissipation was 0).
  const auto ida_scene = load_scene(CSIM_SOURCE_DIR "/scenes/fe-damped-drift/scene.yaml", {"integrator.type=ida"});
  const auto mj_scene = load_scene(CSIM_SOURCE_DIR "/scenes/fe-damped-drift/scene.yaml", {});
  const State ida = run_to_end(*ida_scene), mj = run_to_end(*mj_scene);
  const auto drift = [](const Scene& scene, const State& s) {
    const BodyInstance& bar = scene.world.bodies[0];
    return s.q.segment(bar.position_offset, bar.body->position_size()).mean();
  };
  EXPECT_NEAR(drift(*ida_scene, ida), drift(*mj_scene, mj), 1e-3 * std::abs(drift(*mj_scene, mj)));
  EXPECT_NEAR(ida.energy.kinetic, mj.energy.kinetic, 1e-3 * mj.energy.kinetic);
  EXPECT_GT(mj.energy.damping_dissipation, 1.0);
  EXPECT_NEAR(ida.energy.damping_dissipation, mj.energy.damping_dissipation, 1e-3 * mj.energy.damping_dissipation);
  EXPECT_LT(std::abs(ida.energy.residual()), 1e-5 * ida.energy.damping_dissipation);
}

TEST(IdaOnElasticBodies, ScenesItCannotRunAreRefusedBeforeTheFirstStep) {
  auto refused = [](const std::string& scene, const std::vector<std::string>& overrides, const std::string& words) {
    try {
      load_scene(CSIM_SOURCE_DIR "/scenes/" + scene + "/scene.yaml", overrides);
      ADD_FAILURE() << scene << " was accepted";
    } catch (const SceneError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("integrator.type"), std::string::npos) << message;
      EXPECT_NE(message.find(words), std::string::npos) << message;
      EXPECT_NE(message.find("use "), std::string::npos) << message;  // what to use instead
    }
  };
  refused("sdnv104-quad4", {"integrator.type=ida-events"}, "ida-events does not take elastic bodies");
  refused("ssnv503-2d", {"integrator.type=ida"}, "this scene is quasi-static");
  refused("tied-pendulum", {"integrator.type=ida"}, "prescribed motions");
  refused("sdnd100-a", {"integrator.type=quasi-static"}, "linear constraints");
}

}  // namespace
}  // namespace csim
