// The Moreau–Jean stepper: the lumped benchmark runs against their analytical references, energy of the
// θ-method, constraints that hold in position, exact rigid rotation, a two-body impact against Newton's
// law, and what a step keeps for the next (K v_{k+1}) giving the step of a fresh stepper.
#include "engine/bodies/point_mass.h"
#include "engine/bodies/rigid_body_3d.h"
#include "engine/steppers/moreau_jean.h"
#include "tests/engine/test_worlds.h"
#include "tests/tools/reference/coulomb_oscillator_cases.h"
#include "tools/reference/coulomb_oscillator.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace csim {
namespace {

using test::constrained_point;
using test::oscillator;
using test::point_mass;
using test::start;

// The lumped benchmark runs of bench/bench_bullet.cpp (20 000 steps each, at their steps) against their
// analytical references, at every step. A refactor may move them at round-off; these tolerances are
// what the scheme owes, far above round-off and far below what a wrong step would give.
// A benchmark's scene at step h (s), its scene's stepper and the state that stepper started.
struct BenchmarkRun {
  BenchmarkRun(const std::string& name, double step)
      : scene(load_scene(CSIM_SOURCE_DIR "/scenes/" + name + "/scene.yaml", {"time.step=" + std::to_string(step)})),
        stepper(make_stepper(scene->world, scene->run)), state(initial_state(scene->world)) {
    stepper->initialize(state);
  }
  const BodyInstance& body(const std::string& name) const {
    return scene->world.bodies[scene->world.body_index(name)];
  }
  std::unique_ptr<Scene> scene;
  std::unique_ptr<Stepper> stepper;
  State state;
};

// Steps a benchmark's run `steps` times beside the exact motion of the Coulomb oscillator that models
// it (solved over [0, t_end], s): travel(state) is the body's displacement that the oscillator's x
// stands for (m), check(state, k) the scene's own checks after step k, whose fatal failure ends the run.
// Returns the largest |travel − x(t)| over the steps (m).
template <class Travel, class Check>
double largest_travel_error(BenchmarkRun& run, const CoulombOscillator& model, double t_end, int steps,
                            const Travel& travel, const Check& check) {
  const CoulombOscillatorSolution reference(model, t_end);
  double largest_error = 0.0;
  for (int k = 0; k < steps; ++k) {
    run.stepper->step(run.state);
    largest_error = std::max(largest_error, std::abs(travel(run.state) - reference.position(run.state.t)));
    check(run.state, k);
    if (::testing::Test::HasFatalFailure()) break;
  }
  return largest_error;
}

// A Moreau–Jean stepper on a test World (which must outlive it) and the state it started from rest.
struct SteppedWorld {
  SteppedWorld(const World& world, const MoreauJeanParameters& parameters)
      : stepper(world, parameters), state(start(world)) {
    stepper.initialize(state);
  }
  MoreauJean stepper;
  State state;
};

// Moreau–Jean at step h (s) and θ, the other parameters their defaults.
MoreauJeanParameters steps_of(double step, double theta = MoreauJeanParameters{}.theta) {
  MoreauJeanParameters p;
  p.step = step;
  p.theta = theta;
  return p;
}

// The FE shoe at 10 divisions: a small sparse World with sliding contacts.
std::unique_ptr<Scene> small_fe_shoe() {
  return load_scene(CSIM_SOURCE_DIR "/scenes/sdnv104-quad4/scene.yaml", {"parameters.divisions=10"});
}

// sdnv104-rigid, h = 1e-5 for 0.2 s: the shoe slides from rest (F = 200 kN > μN = 21 kN), its x the
// Coulomb oscillator's exact x(t) = (F − μN)/k (1 − cos ωt) (tools/reference/coulomb_oscillator.h) to
// 1e-7 m (the θ = ½ scheme's error is O(h²) on this smooth slip, and the start from rest O(h²) too: 1e-10
// m of 0.5 m), its y and angle on the support, and the normal impulse N h at each step.
TEST(MoreauJean, RigidShoeFollowsTheCoulombOscillator) {
  const double h = 1e-5;
  BenchmarkRun run("sdnv104-rigid", h);
  const CoulombOscillator model = test::sdnv104(0.0);
  const BodyInstance& shoe = run.body("shoe");
  const auto travel = [&](const State& state) { return state.q(shoe.position_offset) - shoe.reference_position(0); };
  const double largest_error = largest_travel_error(run, model, 0.3, 20000, travel, [&](const State& state, int k) {
    ASSERT_LE(std::abs(state.q(shoe.position_offset + 1) - 0.5), 1e-12) << "step " << k;  // on the support
    ASSERT_LE(std::abs(state.q(shoe.position_offset + 2)), 1e-12) << "step " << k;      // not turned
    double normal = 0.0;
    for (const ActiveContact& c : state.contacts) normal += c.impulse(0);
    ASSERT_NEAR(normal, model.normal_force * h, 1e-9 * model.normal_force * h) << "step " << k;
  });
  if (HasFatalFailure()) return;
  EXPECT_GT(travel(run.state), 0.5);  // slid half a metre by 0.2 s
  EXPECT_LE(largest_error, 1e-7);
}

// incline-3d, h = 1e-5 for 0.2 s: tan 20° < μ = 0.5, the cube must not move; its four contacts carry
// m g cos 20° and m g sin 20° together, each step's impulses m g h times those.
TEST(MoreauJean, CubeOnInclineStaysAtRest) {
  const double h = 1e-5;
  BenchmarkRun run("incline-3d", h);
  State& state = run.state;
  const BodyInstance& block = run.body("block");
  const double angle = 20.0 * M_PI / 180.0, weight = 10.0 * 9.81;
  double largest_move = 0.0, largest_speed = 0.0;
  for (int k = 0; k < 20000; ++k) {
    run.stepper->step(state);
    const Vector moved = state.q.segment(block.position_offset, 3) - block.reference_position.head(3);
    largest_move = std::max(largest_move, moved.lpNorm<Eigen::Infinity>());
    largest_speed = std::max(largest_speed, state.v.segment(block.velocity_offset, 6).lpNorm<Eigen::Infinity>());
    ASSERT_EQ(state.contacts.size(), 4u) << "step " << k;
    double normal = 0.0;
    Eigen::Vector2d tangential = Eigen::Vector2d::Zero();
    for (const ActiveContact& c : state.contacts) {
      normal += c.impulse(0);
      tangential += c.impulse.segment<2>(1);
    }
    // The first steps also close the gap the scene's rounded position leaves (about 1e-16 m), which
    // takes about m g₀ / (hθ) = 2e-10 N·s more, and then stop the velocity that closed it.
    const double tolerance = 1e-9 * weight * h + (k < 2 ? 10.0 * 1e-16 / (0.5 * h) : 0.0);
    ASSERT_NEAR(normal, weight * std::cos(angle) * h, tolerance) << "step " << k;
    ASSERT_NEAR(tangential.norm(), weight * std::sin(angle) * h, tolerance) << "step " << k;
  }
  EXPECT_LE(largest_move, 1e-12);  // m
  EXPECT_LE(largest_speed, 1e-9);  // m/s, rad/s
}

// sdnd100-a, h = 2e-6 for 0.04 s: the pad released from 0.85 mm along the 45° line, its travel along
// the line the Coulomb oscillator's (μ m g = 1 N, k = 1e4 N/m), through its first stop at half a period
// (0.0314 s, at −0.65 mm, from which it slides back); to 1e-3 of the release offset, the scene's own
// tolerance on its extrema.
TEST(MoreauJean, FrictionPadFollowsTheCoulombOscillator) {
  BenchmarkRun run("sdnd100-a", 2e-6);
  const CoulombOscillator model = test::sdnd100(0.1);
  const BodyInstance& pad = run.body("pad");
  const auto moved = [&](const State& state) {
    return Eigen::Vector3d(state.q.segment(pad.position_offset, 3) - pad.reference_position.head(3));
  };
  const auto along = [&](const State& state) {
    const Eigen::Vector3d at = moved(state);
    return (at(0) + at(1)) / std::sqrt(2.0);
  };
  const double largest_error = largest_travel_error(run, model, 0.05, 20000, along, [&](const State& state, int k) {
    const Eigen::Vector3d at = moved(state);
    ASSERT_LE(std::abs(at(0) - at(1)), 1e-12) << "step " << k;  // on the line
  });
  if (HasFatalFailure()) return;
  EXPECT_LE(largest_error, 1e-3 * model.x0);
}

TEST(MoreauJean, HalfThetaConservesEnergyOfAFreeOscillator) {
  const World world = oscillator();
  SteppedWorld run(world, steps_of(1e-3, 0.5));
  State& s = run.state;
  const double e0 = s.energy.kinetic + s.energy.elastic;
  ASSERT_NEAR(e0, 0.5 * 800.0 * 1e-4, 1e-15);
  for (int k = 0; k < 20000; ++k) {
    run.stepper.step(s);
    ASSERT_NEAR(s.energy.kinetic + s.energy.elastic, e0, 1e-10 * e0) << "step " << k;
  }
  EXPECT_LE(s.energy.max_abs_residual, 1e-12 * e0);
  EXPECT_EQ(s.energy.numerical_dissipation, 0.0);  // (θ − ½)(…) at θ = ½, not formed
}

TEST(MoreauJean, ThetaAboveHalfDissipatesAndTheBalanceCloses) {
  const World world = oscillator();
  SteppedWorld run(world, steps_of(1e-3, 0.7));
  State& s = run.state;
  double previous = s.energy.kinetic + s.energy.elastic;
  for (int k = 0; k < 5000; ++k) {
    run.stepper.step(s);
    const double energy = s.energy.kinetic + s.energy.elastic;
    ASSERT_LE(energy, previous * (1 + 1e-14)) << "step " << k;
    previous = energy;
  }
  EXPECT_LT(previous, 0.9 * 0.5 * 800.0 * 1e-4);
  EXPECT_GT(s.energy.numerical_dissipation, 0.0);
  EXPECT_LE(s.energy.max_abs_residual, 1e-12 * 0.5 * 800.0 * 1e-4);
}

TEST(MoreauJean, LinearConstraintHoldsInPositionEveryStep) {
  const World world = constrained_point();
  SteppedWorld run(world, steps_of(1e-2));
  State& s = run.state;
  for (int k = 0; k < 300; ++k) {
    run.stepper.step(s);
    ASSERT_NEAR(s.q(0) - 2.0 * s.q(1), 0.01, 1e-13) << "step " << k;
  }
  // Along the line (2, 1)/√5 the acceleration is (F·e)/m; across it none; z is free.
  const double t = s.t;
  const Eigen::Vector3d e = Eigen::Vector3d(2, 1, 0).normalized();
  EXPECT_NEAR((s.q.head<3>() - Eigen::Vector3d(0.01, 0, 0)).dot(e), 0.5 * (3.0 * e.x()) / 1.5 * t * t, 1e-9);
  EXPECT_NEAR(s.q(2), 0.5 * (-1.0 / 1.5) * t * t, 1e-9);
}

// One rigid body in space at rest in the identity orientation: m = 2 kg, I = (0.1, 0.2, 0.3) kg·m².
World rigid_body_3d_world() {
  World world;
  world.dimension = 3;
  BodyInstance b;
  b.name = "top";
  b.body = std::make_unique<RigidBody3d>(2.0, Eigen::Vector3d(0.1, 0.2, 0.3));
  b.reference_position.setZero(7);
  b.reference_position(3) = 1.0;  // identity quaternion
  b.initial_position = b.reference_position;
  b.initial_velocity.setZero(6);
  world.bodies.push_back(std::move(b));
  world.finalize_layout();
  return world;
}

TEST(MoreauJean, RigidBodySpinningAboutAPrincipalAxisRotatesExactly) {
  World world = rigid_body_3d_world();
  world.bodies[0].initial_velocity(5) = 4.0;  // rad/s about the body z axis
  SteppedWorld run(world, steps_of(1e-3));
  State& s = run.state;
  for (int k = 0; k < 1000; ++k) run.stepper.step(s);
  const Eigen::Quaterniond q(s.q(3), s.q(4), s.q(5), s.q(6));
  const Eigen::Quaterniond expected(Eigen::AngleAxisd(4.0 * s.t, Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(q.angularDistance(expected), 0.0, 1e-12);
  EXPECT_NEAR(s.energy.kinetic, 0.5 * 0.3 * 16.0, 1e-12);
}

TEST(MoreauJean, PrescribedRotationOfA3dRigidBodyTurnsItExactly) {
  // A 3D rotation is prescribed through its rate over each step (its coordinates are a quaternion):
  // the angle about the body's z axis follows the table at every step's end, and the reaction is the
  // torque that spins the body up, I ω̇ (here 0.3 kg·m² × 2 rad/s² on the ramp's first step at θ = 1).
  World world = rigid_body_3d_world();
  PrescribedComponent spin;
  spin.body = 0;
  spin.component = 5;  // rz
  spin.value.table = {{0.0, 0.0}, {1.0, 1.0}, {2.0, 3.0}};  // 1 rad/s, then 2 rad/s
  world.prescribed.push_back(spin);
  const MoreauJeanParameters p = steps_of(1e-2, 1.0);
  SteppedWorld run(world, p);
  State& s = run.state;
  for (int k = 0; k < 200; ++k) {
    run.stepper.step(s);
    const Eigen::Quaterniond q(s.q(3), s.q(4), s.q(5), s.q(6));
    const Eigen::Quaterniond expected(Eigen::AngleAxisd(spin.value(s.t), Eigen::Vector3d::UnitZ()));
    ASSERT_NEAR(q.angularDistance(expected), 0.0, 1e-12) << "t = " << s.t;
    if (k == 100) {
      EXPECT_NEAR(s.reactions(5), 0.3 * (2.0 - 1.0) / p.step, 1e-9);  // I Δω / h
    }
  }
  EXPECT_NEAR(s.v(5), 2.0, 1e-12);
}

// Two disks on a line: the impact follows Newton's law u⁺ = −e u⁻ with momentum conserved.
// Two disks of radius 0.1 m on a line, 0.05 m apart: a (1 kg) at x = 0 moving at +2 m/s, b (3 kg) at
// x = 0.25 m moving at −1 m/s; Newton restitution e.
World two_disks(double e) {
  World world;
  world.dimension = 2;
  world.bodies.push_back(point_mass("a", 2, 1.0, Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 0, 0)));
  world.bodies.push_back(point_mass("b", 2, 3.0, Eigen::Vector3d(0.25, 0, 0), Eigen::Vector3d(-1, 0, 0)));
  for (auto& b : world.bodies) {
    b.shapes.push_back(ShapeInstance{"disk", Sphere{0.1}, Eigen::Isometry3d::Identity()});
    b.body->bounding_radius = 0.1;
  }
  world.finalize_layout();
  ContactLaw law;
  law.body_a = 0;
  law.body_b = 1;
  law.restitution = e;
  world.contact_laws.push_back(law);
  return world;
}

TEST(MoreauJean, TwoBodyImpactFollowsNewtonsLaw) {
  for (const double e : {0.0, 0.4, 1.0}) {
    const World world = two_disks(e);
    SteppedWorld run(world, steps_of(1e-4));
    State& s = run.state;
    for (int k = 0; k < 500; ++k) run.stepper.step(s);
    const double va = s.v(0), vb = s.v(2);
    EXPECT_NEAR(1.0 * va + 3.0 * vb, 1.0 * 2 - 3.0 * 1, 1e-12) << "e = " << e;
    EXPECT_NEAR(vb - va, e * 3.0, 1e-10) << "e = " << e;
    EXPECT_NEAR(s.v(1), 0.0, 1e-14);
    EXPECT_NEAR(s.v(3), 0.0, 1e-14);
  }
}

// The two disks, inelastic, closing at 3 m/s, h = 0.007 s, θ = 1: after two steps the gap is 0.008, less
// than ½ h |u_n| = 0.0105, so the contact is active there. An inelastic contact then closes that gap
// within the step and the disks end touching (momentum kept, relative velocity 0); the textbook rule
// (close_gaps = false) stops them where they were caught, 0.008 apart.
TEST(MoreauJean, InelasticContactClosesItsOpenGapWithinTheStep) {
  for (const bool close_gaps : {true, false}) {
    const World world = two_disks(0.0);
    MoreauJeanParameters p = steps_of(0.007, 1.0);
    p.close_gaps = close_gaps;
    SteppedWorld run(world, p);
    State& s = run.state;
    const double kinetic = s.energy.kinetic;
    for (int k = 0; k < 2; ++k) run.stepper.step(s);
    ASSERT_NEAR(s.q(2) - s.q(0) - 0.2, 0.008, 1e-15);
    ASSERT_TRUE(s.contacts.empty());
    for (int k = 0; k < 10; ++k) run.stepper.step(s);
    EXPECT_NEAR(s.q(2) - s.q(0) - 0.2, close_gaps ? 0.0 : 0.008, 1e-14) << "close_gaps " << close_gaps;
    EXPECT_NEAR(1.0 * s.v(0) + 3.0 * s.v(2), 1.0 * 2 - 3.0 * 1, 1e-12);
    EXPECT_NEAR(s.v(2) - s.v(0), 0.0, 1e-12);
    // The kinetic energy of the relative motion, ½ (m_a m_b / (m_a + m_b)) 3², is dissipated by the
    // contact and θ = 1's numerical damping; the balance closes.
    EXPECT_NEAR(kinetic - s.energy.kinetic, 0.5 * 0.75 * 9.0, 1e-12);
    EXPECT_LE(s.energy.max_abs_residual, 1e-12);
  }
}

// The same disks δ apart, δ within the stage's touching band (1e-9 of the largest body's bounding radius,
// 0.1 m: 1e-10 m), a at 1 m/s into b at rest, θ = 1: such a gap counts as closed already (0), so the
// condition is u_n(v_{k+1}) ≥ 0 and the disks move on together δ apart. Closing δ as well would ask
// for a relative velocity of δ/(hθ) = 5e-8 m/s; in a hyperstatic set the round-off gaps admit no rigid
// motion that closes them all at once, and the contact problem then has no solution.
TEST(MoreauJean, AContactWithinTheTouchingBandKeepsItsGap) {
  const double delta = 0.5e-10, h = 1e-3;
  World world = two_disks(0.0);
  world.bodies[0].initial_velocity << 1.0, 0.0;
  world.bodies[1].initial_position << 0.2 + delta, 0.0;
  world.bodies[1].initial_velocity << 0.0, 0.0;
  SteppedWorld run(world, steps_of(h, 1.0));
  State& s = run.state;
  const double gap = s.q(2) - s.q(0) - 0.2;
  run.stepper.step(s);
  ASSERT_EQ(s.contacts.size(), 1u);
  EXPECT_NEAR(s.v(0), 0.25, 1e-12);  // momentum 1 kg · 1 m/s shared by 4 kg
  EXPECT_NEAR(s.v(2) - s.v(0), 0.0, 1e-12);
  EXPECT_NEAR(s.q(2) - s.q(0) - 0.2, gap, 1e-15);
}

// Three disks in a row, equal masses, e = 0: a at 1 m/s touching b, b at rest g = 1e-4 m from c at rest.
// Step 2's rule sees no motion between b and c (their free velocities are 0), but a's impulse sends b
// at ½ m/s, and over h = 1e-3 at θ = ½ the step would carry b 2.5e-4 m, into c by 1.5e-4 m. The step's
// motion closes the gap. Every inelastic candidate is a row of the step's problem (moreau_jean.h, step
// 2), so the one solve holds it: b stops on c's surface (its gap closed to round-off, not overlapping),
// and the three share the momentum.
TEST(MoreauJean, AContactThatTheStepsMotionClosesIsHeldByTheSameSolve) {
  const double g = 1e-4, h = 1e-3;
  World world;
  world.dimension = 2;
  world.bodies.push_back(point_mass("a", 2, 1.0, Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)));
  world.bodies.push_back(point_mass("b", 2, 1.0, Eigen::Vector3d(0.2, 0, 0), Eigen::Vector3d(0, 0, 0)));
  world.bodies.push_back(point_mass("c", 2, 1.0, Eigen::Vector3d(0.4 + g, 0, 0), Eigen::Vector3d(0, 0, 0)));
  for (auto& b : world.bodies) {
    b.shapes.push_back(ShapeInstance{"disk", Sphere{0.1}, Eigen::Isometry3d::Identity()});
    b.body->bounding_radius = 0.1;
  }
  world.finalize_layout();
  for (const auto& [a, b] : {std::pair{0, 1}, std::pair{1, 2}}) {
    ContactLaw law;
    law.body_a = a;
    law.body_b = b;
    world.contact_laws.push_back(law);
  }
  SteppedWorld run(world, steps_of(h, 0.5));
  State& s = run.state;
  run.stepper.step(s);
  EXPECT_EQ(s.counters.solves, 1);
  ASSERT_EQ(s.contacts.size(), 2u);
  EXPECT_NEAR(s.q(4) - s.q(2) - 0.2, 0.0, 1e-12);  // b on c's surface, neither apart nor into it
  // a strikes b at gap 0: the θ-scheme's own overlap at an impact, h (1 − θ) · 1 m/s, as before.
  EXPECT_NEAR(s.q(2) - s.q(0) - 0.2, -h * 0.5, 1e-12);
  EXPECT_NEAR(s.v(0) + s.v(2) + s.v(4), 1.0, 1e-12);  // momentum
}

TEST(MoreauJean, NonFiniteStateStopsWithTheTime) {
  World world = oscillator();
  world.springs[0].stiffness = std::numeric_limits<double>::infinity();
  const MoreauJeanParameters p{};
  SteppedWorld run(world, p);
  try {
    run.stepper.step(run.state);
    FAIL() << "expected a RunError";
  } catch (const RunError& error) {
    EXPECT_NEAR(error.time, p.step, 1e-15);
    EXPECT_NE(std::string(error.what()).find("non-finite"), std::string::npos);
  }
}

// A sparse linear World keeps K v_{k+1} from the energy balance for the next step's free velocity
// (moreau_jean.h). From the same state, the stepper that kept it and a fresh one take the same step to
// the bit, also when the velocity was changed between two steps (the kept product is then stale).
TEST(MoreauJean, KeptStiffnessProductGivesAFreshSteppersStep) {
  const auto scene = small_fe_shoe();
  const MoreauJeanParameters p = moreau_jean_parameters(scene->run);
  for (const bool change_velocity : {false, true}) {
    MoreauJean kept(scene->world, p);
    State s = initial_state(scene->world);
    kept.initialize(s);
    for (int k = 0; k < 300; ++k) kept.step(s);  // sliding on its contacts by now
    ASSERT_FALSE(s.contacts.empty());
    if (change_velocity) s.v *= 0.5;
    State fresh_state = s;
    MoreauJean fresh(scene->world, p);
    kept.step(s);
    fresh.step(fresh_state);
    EXPECT_TRUE(s.v == fresh_state.v) << (change_velocity ? "velocity changed" : "same velocity");
    EXPECT_TRUE(s.q == fresh_state.q);
  }
}

// A World stepped side by side in two halves and with v_free formed whole (moreau_jean.h).
struct HalvesAndWhole {
  static MoreauJeanParameters whole(MoreauJeanParameters p) {
    p.two_halves = false;
    return p;
  }
  HalvesAndWhole(const World& world, const RunSettings& run)
      : split(world, moreau_jean_parameters(run)), formed(world, whole(moreau_jean_parameters(run))),
        halves(initial_state(world)), reference(halves) {
    split.initialize(halves);
    formed.initialize(reference);
  }
  void step() {
    split.step(halves);
    formed.step(reference);
  }
  double velocity_gap() const {  // relative, ∞-norm
    return (halves.v - reference.v).lpNorm<Eigen::Infinity>() / reference.v.lpNorm<Eigen::Infinity>();
  }
  MoreauJean split, formed;
  State halves, reference;
};

// Two halves take the steps of the whole free velocity to the contact solver's tolerance (1e-10
// relative here), with the same contacts at every step; the start from rest (v_k = 0, a margin of
// round-off) is a step taken again.
TEST(MoreauJean, TwoHalvesTakeTheStepsOfTheWholeFreeVelocity) {
  const auto scene = small_fe_shoe();
  HalvesAndWhole run(scene->world, scene->run);
  const State &a = run.halves, &b = run.reference;
  double velocity_gap = 0.0, position_gap = 0.0;
  for (int k = 0; k < 500; ++k) {
    run.step();
    ASSERT_EQ(a.contacts.size(), b.contacts.size()) << "step " << k;
    velocity_gap = std::max(velocity_gap, run.velocity_gap());
    position_gap = std::max(position_gap, (a.q - b.q).lpNorm<Eigen::Infinity>() / b.q.lpNorm<Eigen::Infinity>());
  }
  EXPECT_GT(a.contacts.size(), 0u);
  EXPECT_LT(velocity_gap, 1e-8);
  EXPECT_LT(position_gap, 1e-10);
  EXPECT_GT(velocity_gap, 0.0);  // the two paths are distinct
  EXPECT_GE(a.counters.detections_retaken, 1);  // the first step, from rest
  EXPECT_LE(a.counters.detections_retaken, 5);
  EXPECT_EQ(b.counters.detections_retaken, 0);
  EXPECT_EQ(a.counters.contact_points, b.counters.contact_points);
}

// Two halves with an equality row: the shoe's top corners held at the same x displacement (a linear
// constraint on two nodes of a sparse World) hold in position at every step, and the steps are those of
// the whole free velocity to the contact solver's tolerance.
TEST(MoreauJean, TwoHalvesHoldALinearConstraintOfASparseWorld) {
  auto scene = small_fe_shoe();
  World& world = scene->world;
  const BodyInstance& shoe = world.bodies[0];
  ASSERT_TRUE(shoe.body->elastic());
  int left = -1, right = -1;  // the x coordinates of the nodes at (0, 1) and (1, 1)
  for (int node = 0; 2 * node < shoe.body->position_size(); ++node) {
    if (shoe.body->node_reference(node) == Eigen::Vector3d(0, 1, 0)) left = 2 * node;
    if (shoe.body->node_reference(node) == Eigen::Vector3d(1, 1, 0)) right = 2 * node;
  }
  ASSERT_GE(left, 0);
  ASSERT_GE(right, 0);
  world.constraints.push_back({"top_corners", {{shoe.velocity_offset + left, 1.0}, {shoe.velocity_offset + right, -1.0}}, 0.0});
  HalvesAndWhole run(world, scene->run);
  const auto displacement = [&](int c) { return run.halves.q(shoe.position_offset + c) - shoe.reference_position(c); };
  double held = 0.0, velocity_gap = 0.0;
  for (int k = 0; k < 300; ++k) {
    run.step();
    held = std::max(held, std::abs(displacement(left) - displacement(right)));
    velocity_gap = std::max(velocity_gap, run.velocity_gap());
  }
  EXPECT_LT(held, 1e-12);
  EXPECT_LT(velocity_gap, 1e-8);
  EXPECT_GT(displacement(left), 1e-3);  // the shoe slid
}

// A box released 1e-7 m above an elastic block (3D, sparse) lands within its first step: the margin
// of two halves, from v_0 = 0, does not reach the block, and the step taken again over v_free's margin
// catches the landing as the whole free velocity does, with no penetration.
TEST(MoreauJean, TwoHalvesTakeAgainAStepThatOutranItsMargin) {
  const auto scene = load_scene(CSIM_SOURCE_DIR "/scenes/box-on-block-3d/scene.yaml", {"parameters.drop=1e-7"});
  HalvesAndWhole run(scene->world, scene->run);
  run.step();
  const State &a = run.halves, &b = run.reference;
  EXPECT_EQ(a.counters.detections_retaken, 1);
  ASSERT_FALSE(b.contacts.empty());
  EXPECT_EQ(a.contacts.size(), b.contacts.size());
  EXPECT_LE(run.velocity_gap(), 1e-9);
  EXPECT_LE((a.q - b.q).lpNorm<Eigen::Infinity>(), 1e-12);
}

}  // namespace
}  // namespace csim
