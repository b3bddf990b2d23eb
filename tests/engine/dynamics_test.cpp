// Springs and loads as generalized forces: directions, signs, torques, energies, time functions.
#include "engine/bodies/point_mass.h"
#include "engine/bodies/rigid_body_2d.h"
#include "engine/bodies/rigid_body_3d.h"
#include "engine/dynamics.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"
#include "engine/steppers/ida_integrator.h"

#include <gtest/gtest.h>

#include <cstring>

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

// A spring's force on its two ends does not depend on which end is named first, to the bit: swapping
// them negates the stretch exactly, and each end's generalized force is its columns against the force
// on it (end A's added, end B's subtracted). A turned rigid body and a point, along a direction and not.
TEST(Forces, ASpringsEndsSwappedGiveTheSameForcesToTheBit) {
  World world;
  world.dimension = 2;
  world.bodies.push_back(make("plate", std::make_unique<RigidBody2d>(3.0, 0.4), Eigen::Vector3d(0.0, 0.0, 0.0)));
  world.bodies.push_back(make("particle", std::make_unique<PointMass>(2, 1.0), Eigen::Vector2d(1.5, 0.25)));
  world.finalize_layout();
  Vector q(5);
  q << 0.013, -0.021, 0.37, 1.49, 0.31;
  for (const Eigen::Vector3d& direction : {Eigen::Vector3d::Zero().eval(), Eigen::Vector3d(0.6, 0.8, 0.0).eval()}) {
    Spring forward;
    forward.body_a = 0;
    forward.point_a = Eigen::Vector3d(0.5, -0.2, 0.0);
    forward.body_b = 1;
    forward.stiffness = 700.0;
    forward.direction = direction;
    Spring backward = forward;
    std::swap(backward.body_a, backward.body_b);
    std::swap(backward.point_a, backward.point_b);
    Vector f_forward = Vector::Zero(5), f_backward = Vector::Zero(5);
    world.springs = {forward};
    Dynamics(world).add_spring_forces(q, f_forward);
    world.springs = {backward};
    Dynamics(world).add_spring_forces(q, f_backward);
    EXPECT_GT(f_forward.norm(), 1.0);
    EXPECT_EQ(std::memcmp(f_forward.data(), f_backward.data(), sizeof(double) * 5), 0)
        << f_forward.transpose() << "\n" << f_backward.transpose();
  }
}

// A load at a rigid body's origin, and its weight, have no moment whatever the body's turn: Dynamics
// takes their Jacobian once, without the rotations' columns (the weight: once formed), and must give
// the force of the turned body's full Jacobian to the bit (its columns summed in order, as for a load
// off the origin, which keeps turning).
TEST(Forces, ALoadAtARigidBodysOriginIsThatOfItsTurnedJacobianToTheBit) {
  for (const int dimension : {2, 3}) {
    World world;
    world.dimension = dimension;
    world.gravity = dimension == 2 ? Eigen::Vector3d(1.5, -9.81, 0.0) : Eigen::Vector3d(1.5, 0.0, -9.81);
    Vector q_ref;
    if (dimension == 2) {
      q_ref = Eigen::Vector3d(0.5, 0.5, 0.0);
      world.bodies.push_back(make("shoe", std::make_unique<RigidBody2d>(7.0, 2.0), q_ref));
    } else {
      q_ref.setZero(7);
      q_ref(3) = 1.0;  // the identity quaternion
      world.bodies.push_back(make("block", std::make_unique<RigidBody3d>(7.0, Eigen::Vector3d(1.0, 2.0, 3.0)), q_ref));
    }
    world.finalize_layout();
    for (const Eigen::Vector3d& point : {Eigen::Vector3d::Zero().eval(), Eigen::Vector3d(0.5, -0.5, 0.25).eval()}) {
      Load load;
      load.body = 0;
      load.point = dimension == 2 ? Eigen::Vector3d(point.x(), point.y(), 0.0) : point;
      load.force = Eigen::Vector3d(2e5, -7e4, dimension == 2 ? 0.0 : 3e4);
      load.multiplier.table = {{0.0, 0.75}};  // λ = 0.75 at every t
      world.loads = {load};
      const Dynamics dynamics(world);
      Vector q = q_ref;
      if (dimension == 2) {
        q << 0.7, 0.4, -8.5e-22;  // turned by round-off, as the sliding shoe is
      } else {
        const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 2).normalized()));
        q << 0.1, -0.2, 0.3, turn.w(), turn.x(), turn.y(), turn.z();
      }
      Vector f;
      dynamics.external(q, 1.0, f);
      const PointJacobian J = world.bodies[0].body->point_jacobian(q, load.point);
      Vector expected = Vector::Zero(world.velocity_size);
      world.bodies[0].body->add_weight(q, world.gravity, expected);
      for (int k = 0; k < J.count; ++k) expected(J.index[k]) += J.column.col(k).dot(0.75 * load.force);
      ASSERT_EQ(f.size(), expected.size());
      EXPECT_EQ(std::memcmp(f.data(), expected.data(), sizeof(double) * f.size()), 0)
          << "dimension " << dimension << ", point " << load.point.transpose() << ":\n" << f.transpose() << "\n"
          << expected.transpose();
      // Off the origin the load has a moment (so that the comparison above covers a turning Jacobian).
      const int rotation = dimension == 2 ? 2 : 3;
      EXPECT_EQ(f(rotation) != 0.0, !load.point.isZero()) << "dimension " << dimension;
    }
  }
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


// ---------------------------------------------------------------------------------------------------
// One smooth stage for every stepper: a World with every body and force type (data/every_force.yaml)
// goes through Moreau–Jean, the quasi-static stepper and IDA, and each must integrate the same
// M v̇ = f(t, q, v) of Dynamics. A force that one stepper sums and another forgets fails here.
namespace every_force {

const char* kScene = CSIM_SOURCE_DIR "/tests/engine/data/every_force.yaml";

// The parts of f at (t, q, v), to judge a residual against each of them.
struct Parts {
  Vector total, loads, internal, damping;
};
Parts parts(const Dynamics& dynamics, double t, const Vector& q, const Vector& v) {
  Parts p;
  dynamics.force(t, q, v, p.total, &p.loads, &p.damping);
  p.internal = Vector::Zero(q.size() == v.size() ? v.size() : dynamics.size());
  dynamics.add_internal_forces(q, p.internal);
  return p;
}

TEST(Dynamics, MoreauJeanThetaOneStepsTheSmoothStagesEquationOfMotion) {
  // θ = 1: M (v_{k+1} − v_k) = h f(t_{k+1}, q_{k+1}, v_{k+1}), up to the loads' points and the springs'
  // directions taken at q_k (O(h ω) on the turning plate), to Newton's tolerance on the neo-Hookean block.
  const auto scene = load_scene(kScene, {"time.step=1e-4"});
  const Dynamics dynamics(scene->world);
  auto stepper = make_stepper(scene->world, scene->run);
  State state = initial_state(scene->world);
  stepper->initialize(state);
  for (int k = 0; k < 99; ++k) stepper->step(state);  // deformed, damped, loaded
  const Vector v0 = state.v;
  stepper->step(state);
  const double h = 1e-4;
  const Parts f = parts(dynamics, state.t, state.q, state.v);
  const Vector residual = dynamics.mass() * (state.v - v0) / h - f.total;
  // Each part must matter, so that leaving one out would fail the test by far.
  for (const Vector* part : {&f.loads, &f.internal, &f.damping}) EXPECT_GT(part->norm(), 0.5);
  const double smallest = std::min({f.loads.norm(), f.internal.norm(), f.damping.norm()});
  EXPECT_LT(residual.norm(), 2e-3 * smallest) << "residual " << residual.norm();
}

TEST(Dynamics, QuasiStaticEquilibriumIsTheSmoothStagesAtRest) {
  // No inertia, no damping: f(t, q, 0) = 0 at every converged load step.
  const auto scene = load_scene(kScene, {"integrator.type=quasi-static"});
  const Dynamics dynamics(scene->world);
  auto stepper = make_stepper(scene->world, scene->run);
  State state = initial_state(scene->world);
  state.v.setZero();
  stepper->initialize(state);
  stepper->step(state);
  const Vector at_rest = Vector::Zero(dynamics.size());
  const Parts f = parts(dynamics, state.t, state.q, at_rest);
  EXPECT_GT(f.loads.norm(), 10.0);
  EXPECT_LT(f.total.norm(), 1e-8 * f.loads.norm()) << f.total.transpose();
}

TEST(Dynamics, IdaResidualIsMassTimesAccelerationLessTheSmoothStage) {
  const auto scene = load_scene(kScene, {"integrator.type=ida"});
  const Dynamics dynamics(scene->world);
  IdaIntegrator ida(scene->world, ida_parameters(scene->run));
  State state = initial_state(scene->world);
  ida.initialize(state);
  ida.step(state);
  const int nq = scene->world.position_size, nv = scene->world.velocity_size;
  const int size = nq + nv + 3;  // (q, v, work of loads, contact and damping dissipation)
  Vector y = Vector::Zero(size), rate = Vector::Zero(size), r(size);
  y.head(nq) = state.q;
  y.segment(nq, nv) = state.v;
  rate.segment(nq, nv) = Vector::LinSpaced(nv, -1.0, 1.0);  // any acceleration
  ASSERT_EQ(ida.residual(state.t, y.data(), rate.data(), r.data()), 0);
  const Parts f = parts(dynamics, state.t, state.q, state.v);
  const Vector expected = dynamics.mass() * rate.segment(nq, nv) - f.total;
  EXPECT_LT((r.segment(nq, nv) - expected).norm(), 1e-12 * f.total.norm());
  EXPECT_NEAR(r(nq + nv), -f.loads.dot(state.v), 1e-12 * f.loads.norm());          // work of loads
  EXPECT_NEAR(r(nq + nv + 2), f.damping.dot(state.v), 1e-12 * f.damping.norm());   // damping: D' = vᵀCv
}

TEST(Dynamics, IdaAndMoreauJeanFollowTheSameTrajectory) {
  // Two discretizations of the same M v̇ = f: IDA at rtol 1e-10 and the trapezoidal rule (θ = ½) at
  // h = 2e-5, whose error is O(h²) ≈ 1e-8 of the motion here.
  const auto mj_scene = load_scene(kScene, {"integrator.theta=0.5", "time.step=2e-5"});
  const auto ida_scene = load_scene(kScene, {"integrator.type=ida", "integrator.rtol=1e-10", "integrator.atol=1e-12"});
  auto mj = make_stepper(mj_scene->world, mj_scene->run);
  auto ida = make_stepper(ida_scene->world, ida_scene->run);
  State a = initial_state(mj_scene->world), b = initial_state(ida_scene->world);
  mj->initialize(a);
  ida->initialize(b);
  while (a.t < 0.01 - 1e-12) mj->step(a);
  while (b.t < 0.01 - 1e-12) ida->step(b);
  const Vector moved = a.q - initial_state(mj_scene->world).q;
  EXPECT_LT((a.q - b.q).norm(), 1e-5 * moved.norm()) << (a.q - b.q).norm() << " of " << moved.norm();
  EXPECT_LT((a.v - b.v).norm(), 1e-4 * a.v.norm());
}

// The loads at two times in one pass (the Moreau–Jean step's ends) are those of two calls, to the bit,
// on a World with every load type, while the loads ramp and after, at a deformed, turned state.
TEST(Dynamics, LoadsAtTwoTimesAreTwoCallsToTheBit) {
  const auto scene = load_scene(kScene, {"time.step=1e-4"});
  const Dynamics dynamics(scene->world);
  auto stepper = make_stepper(scene->world, scene->run);
  State state = initial_state(scene->world);
  stepper->initialize(state);
  for (int k = 0; k < 50; ++k) stepper->step(state);
  for (const auto& [t_a, t_b] : {std::pair{0.0051, 0.005}, std::pair{0.3, 0.7}, std::pair{20.0, 20.0}}) {
    Vector f_a, f_b, one_a, one_b;
    dynamics.external(state.q, t_a, t_b, f_a, f_b);
    dynamics.external(state.q, t_a, one_a);
    dynamics.external(state.q, t_b, one_b);
    EXPECT_TRUE(f_a == one_a && f_b == one_b) << t_a << ", " << t_b;
    EXPECT_GT(f_a.norm(), 0.0);
  }
}

}  // namespace every_force

// A linear elastic body's K u is kept for the next call at the same q (Dynamics::elastic_energy then
// add_internal_forces, as a Moreau–Jean step asks): the force and energy at any q are those of a fresh
// Dynamics, whatever was asked before.
TEST(Dynamics, KeptStiffnessProductFollowsThePositions) {
  const auto scene = load_scene(CSIM_SOURCE_DIR "/scenes/sdnv104-quad4/scene.yaml", {"parameters.divisions=6"});
  const World& world = scene->world;
  const Dynamics dynamics(world);
  const Vector q0 = initial_state(world).q;
  Vector q1 = q0, q2 = q0;
  for (int i = 0; i < q1.size(); ++i) {
    q1(i) += 1e-3 * std::sin(1.0 + i);
    q2(i) += 1e-3 * std::cos(2.0 + i);
  }
  auto internal = [&](const Dynamics& d, const Vector& q) {
    Vector f = Vector::Zero(d.size());
    d.add_internal_forces(q, f);
    return f;
  };
  const double energy1 = dynamics.elastic_energy(q1);
  ASSERT_GT(energy1, 0.0);
  const Vector f1 = internal(dynamics, q1);  // from the kept product
  const Vector f2 = internal(dynamics, q2);  // another q: a new product
  const double energy2 = dynamics.elastic_energy(q2);
  const Dynamics fresh(world);
  EXPECT_TRUE(f1 == internal(fresh, q1));
  EXPECT_TRUE(f2 == internal(Dynamics(world), q2));
  EXPECT_EQ(energy1, Dynamics(world).elastic_energy(q1));
  EXPECT_EQ(energy2, Dynamics(world).elastic_energy(q2));
  EXPECT_GT((f1 - f2).norm(), 1e-3 * f1.norm());
}

// The springs' projected displacements are kept for the last q (a step's elastic energy at q_{k+1},
// the next step's spring forces there): forces and energies are a fresh Dynamics' to the bit, at the
// kept q and at another one that differs in the shoe's angle alone (by round-off of it).
TEST(Dynamics, KeptSpringStrainsFollowThePositions) {
  const auto scene = load_scene(CSIM_SOURCE_DIR "/scenes/sdnv104-rigid/scene.yaml", {});
  const World& world = scene->world;
  const Dynamics dynamics(world);
  const int angle = world.bodies[world.body_index("shoe")].position_offset + 2;
  Vector q1 = initial_state(world).q;
  q1(0) += 0.3;
  q1(angle) += 0.2;
  Vector q2 = q1;
  q2(angle) = std::nextafter(q2(angle), 1.0);
  auto internal = [&](const Dynamics& d, const Vector& q) {
    Vector f = Vector::Zero(d.size());
    d.add_internal_forces(q, f);
    return f;
  };
  const double energy1 = dynamics.elastic_energy(q1);
  const Vector f1 = internal(dynamics, q1);  // from the kept strains
  const Vector f2 = internal(dynamics, q2);  // another q: new strains
  const double energy2 = dynamics.elastic_energy(q2);
  EXPECT_EQ(std::memcmp(f1.data(), internal(Dynamics(world), q1).data(), f1.size() * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(f2.data(), internal(Dynamics(world), q2).data(), f2.size() * sizeof(double)), 0);
  EXPECT_EQ(energy1, Dynamics(world).elastic_energy(q1));
  EXPECT_EQ(energy2, Dynamics(world).elastic_energy(q2));
  EXPECT_GT(energy1, 0.0);
  EXPECT_FALSE(f1 == f2);  // the angle's last bit moves the torques
}

// ½ vᵀ M v with M x in the same pass over M (a Moreau–Jean step's energy balance) gives each the same
// bits as its own product, on an elastic body's consistent mass.
TEST(Dynamics, KineticEnergyWithAMassProductIsBothProducts) {
  const auto scene = load_scene(CSIM_SOURCE_DIR "/scenes/sdnv104-quad4/scene.yaml", {"parameters.divisions=6"});
  const Dynamics dynamics(scene->world);
  Vector v(dynamics.size()), x(dynamics.size());
  for (int i = 0; i < v.size(); ++i) {
    v(i) = std::sin(1.0 + 3.0 * i) * (1.0 + i);
    x(i) = 1e-3 * std::cos(2.0 + i) / (1.0 + i);
  }
  Vector Mx;
  const double kinetic = dynamics.kinetic_energy(v, x, Mx);
  EXPECT_EQ(kinetic, dynamics.kinetic_energy(v));
  const Vector expected = dynamics.mass() * x;
  EXPECT_TRUE(Mx == expected);
  EXPECT_GT(Mx.norm(), 0.0);
}

// An elastic body's weight is formed once by Dynamics (it reads all of M): at any q it is the body's own
// add_weight into zeros, to the bit (box-on-block-3d: a HEXA8 block under gravity; the box on it
// carries the push load too, and is not compared).
TEST(Dynamics, ElasticWeightFormedOnceIsTheBodysWeight) {
  const auto scene = load_scene(CSIM_SOURCE_DIR "/scenes/box-on-block-3d/scene.yaml", {});
  const World& world = scene->world;
  ASSERT_FALSE(world.gravity.isZero());
  const Dynamics dynamics(world);
  Vector q = initial_state(world).q;
  for (int i = 0; i < q.size(); ++i) q(i) += 1e-3 * std::sin(1.0 + i);
  Vector f;
  dynamics.external(q, 0.0, f);
  int elastic = 0;
  for (const BodyInstance& b : world.bodies) {
    if (!b.body->elastic()) continue;
    Vector expected = Vector::Zero(b.body->velocity_size());
    b.body->add_weight(b.positions(q), world.gravity, expected);
    EXPECT_TRUE(f.segment(b.velocity_offset, b.body->velocity_size()) == expected) << b.name;
    EXPECT_GT(expected.norm(), 0.0);
    ++elastic;
  }
  EXPECT_EQ(elastic, 1);
}

// The springs' evaluation is kept for the next question at the same q (springs.h): their forces, energy
// and Jacobian columns must be a fresh evaluation's to the bit whichever was asked first, and after a
// question at another q, at turned and moved positions (sdnv104's shoe on two springs off its centre, a
// pad on a grounded spring, the every-force scene's bodies).
TEST(Dynamics, KeptSpringEvaluationIsAFreshOneToTheBit) {
  for (const std::string& scene_file : {std::string(CSIM_SOURCE_DIR "/scenes/sdnv104-rigid/scene.yaml"),
                                       std::string(CSIM_SOURCE_DIR "/scenes/sdnd100-a/scene.yaml"), std::string(every_force::kScene)}) {
    const auto scene = load_scene(scene_file, {});
    const Dynamics energy_first(scene->world), forces_first(scene->world), columns_first(scene->world);
    const State start = initial_state(scene->world);
    int compared = 0;
    for (int trial = 0; trial < 20; ++trial) {
      Vector q_1 = start.q, q_2 = start.q;
      for (int i = 0; i < q_1.size(); ++i) {
        q_1(i) += 1e-3 * std::sin(1.7 * trial + 0.3 * i) * (trial % 3 == 0 ? 1e-20 : 1.0);
        q_2(i) += 2e-3 * std::cos(0.9 * trial + 0.7 * i);
      }
      for (const Vector* q : {&q_1, &q_2, &q_1}) {
        struct Answers {
          Vector forces;
          double energy = 0.0;
          std::vector<double> columns;
        };
        Answers answers[3];
        const Dynamics* asked[3] = {&energy_first, &forces_first, &columns_first};
        for (int d = 0; d < 3; ++d) {
          Answers& a = answers[d];
          a.forces = Vector::Constant(energy_first.size(), 0.25);
          if (d == 0) a.energy = asked[d]->elastic_energy(*q);
          if (d == 2) asked[d]->spring_jacobian_columns(*q, a.columns);
          asked[d]->add_spring_forces(*q, a.forces);
          if (d != 0) a.energy = asked[d]->elastic_energy(*q);
          if (d != 2) asked[d]->spring_jacobian_columns(*q, a.columns);
        }
        for (int d = 1; d < 3; ++d) {
          ASSERT_EQ(std::memcmp(answers[0].forces.data(), answers[d].forces.data(), answers[0].forces.size() * sizeof(double)), 0)
              << scene_file;
          ASSERT_EQ(std::memcmp(&answers[0].energy, &answers[d].energy, sizeof(double)), 0) << scene_file;
          ASSERT_EQ(answers[0].columns.size(), answers[d].columns.size()) << scene_file;
          ASSERT_EQ(std::memcmp(answers[0].columns.data(), answers[d].columns.data(), answers[0].columns.size() * sizeof(double)), 0)
              << scene_file;
        }
        if (q == &q_2) {
          EXPECT_NE(answers[0].forces, Vector::Constant(energy_first.size(), 0.25)) << scene_file;
        }
        ++compared;
      }
    }
    EXPECT_EQ(compared, 60);
  }
}

// A dense A is kept while the springs' Jacobian columns are the same (structural_operators.h): the
// comparison where they are must tell any change of one column entry (a zero's sign included: the same
// bits give the same K to the bit), or of their number.
TEST(Dynamics, SameSpringJacobianColumnsTellsEveryChange) {
  const auto scene = load_scene(CSIM_SOURCE_DIR "/scenes/sdnv104-rigid/scene.yaml", {});
  const Dynamics dynamics(scene->world);
  Vector q = initial_state(scene->world).q;
  q(2) = 0.3;  // turned: the rotation columns have no zero entry in the plane
  std::vector<double> columns;
  dynamics.spring_jacobian_columns(q, columns);
  ASSERT_EQ(columns.size(), 18u);  // two springs, three columns of one end each
  EXPECT_TRUE(dynamics.same_spring_jacobian_columns(q, columns));
  int zeros = 0;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    std::vector<double> changed = columns;
    changed[i] = std::nextafter(changed[i], 2.0);
    EXPECT_FALSE(dynamics.same_spring_jacobian_columns(q, changed)) << i;
    if (columns[i] != 0.0) continue;
    changed[i] = -columns[i];  // a zero of the other sign: equal, not the same bits
    EXPECT_FALSE(dynamics.same_spring_jacobian_columns(q, changed)) << i;
    ++zeros;
  }
  EXPECT_EQ(zeros, 10);  // a translation's two zeros and the rotation column's z, at each end
  std::vector<double> shorter(columns.begin(), columns.end() - 1), longer = columns;
  longer.push_back(0.0);
  EXPECT_FALSE(dynamics.same_spring_jacobian_columns(q, shorter));
  EXPECT_FALSE(dynamics.same_spring_jacobian_columns(q, longer));
  Vector turned = q;
  turned(2) = 0.31;
  EXPECT_FALSE(dynamics.same_spring_jacobian_columns(turned, columns));
}

}  // namespace
}  // namespace csim
