// Projected Gauss–Seidel on small problems whose solutions are known by hand.
#include "contact/pgs_solver.h"
#include "tests/contact/test_problems.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace csim {
namespace {

constexpr double kGravity = 9.81;  // m/s²
constexpr double kStep = 0.01;     // s

// A 2D rigid box (mass m, inertia I about its centre) at rest on the ground, touching it at its two
// bottom corners (∓a, −b) relative to the centre, frame n = (0, 1), t = (1, 0). Generalised velocity
// (v_x, v_y, ω); the velocity of the corner p is v + ω × p = (v_x − ω p_y, v_y + ω p_x), so the rows of
// H are n: (0, 1, p_x), t: (1, 0, −p_y). A horizontal push F through the centre acts for one step.
struct BoxOnTwoCorners {
  double m = 2.0;       // kg
  double a = 1.0;       // m, half width
  double b = 0.5;       // m, half height
  double I = m * (4 * a * a + 4 * b * b) / 12.0;  // kg·m²
  double mu = 0.3;

  Eigen::Matrix<double, 4, 3> H() const {
    Eigen::Matrix<double, 4, 3> H;
    H << 0, 1, -a,  // corner 1 normal
        1, 0, b,    // corner 1 tangent
        0, 1, a,    // corner 2 normal
        1, 0, b;    // corner 2 tangent
    return H;
  }

  FrictionContactProblem problem(double push) const {
    const Eigen::Matrix3d M_inverse = Eigen::Vector3d(1 / m, 1 / m, 1 / I).asDiagonal();
    const Eigen::Vector3d v_free(kStep * push / m, -kGravity * kStep, 0.0);
    FrictionContactProblem problem;
    problem.dimension = 2;
    problem.contacts = 2;
    problem.W = H() * M_inverse * H().transpose();
    problem.b = H() * v_free;
    problem.mu = {Eigen::Vector2d(mu, mu), Eigen::Vector2d(mu, mu)};
    return problem;
  }

  double weight_impulse() const { return m * kGravity * kStep; }  // N·s
};

Eigen::VectorXd velocity(const FrictionContactProblem& problem, const Eigen::VectorXd& r) {
  return problem.W * r + problem.b;
}

TEST(PgsSolver, EmptyProblemConvergesImmediately) {
  FrictionContactProblem problem;
  problem.W.resize(0, 0);
  problem.b.resize(0);
  Eigen::VectorXd r(3);
  std::vector<ContactStatus> status(4);
  const PgsStatistics statistics = PgsSolver().solve(problem, r, &status);
  EXPECT_TRUE(statistics.converged);
  EXPECT_EQ(statistics.iterations, 0);
  EXPECT_EQ(statistics.residual, 0.0);
  EXPECT_EQ(r.size(), 0);
  EXPECT_TRUE(status.empty());
}

TEST(PgsSolver, SingleContactConvergesToTheLocalSolution) {
  // 3D, coupled W, sliding: the local solve is the global solve.
  FrictionContactProblem problem;
  problem.dimension = 3;
  problem.contacts = 1;
  problem.W.resize(3, 3);
  problem.W << 1.0, 0.1, -0.05, 0.1, 0.9, 0.2, -0.05, 0.2, 0.7;
  problem.b = Eigen::Vector3d(-1.0, 0.6, -0.4);
  problem.mu = {Eigen::Vector2d(0.3, 0.2)};
  Eigen::VectorXd r;  // wrong size: zeroed
  std::vector<ContactStatus> status;
  const PgsStatistics statistics = PgsSolver().solve(problem, r, &status);
  EXPECT_TRUE(statistics.converged);
  // One sweep: after it the contact is settled (its local solution is its impulse), which the
  // residual then confirms exactly, without a second sweep.
  EXPECT_EQ(statistics.iterations, 1);
  EXPECT_EQ(statistics.residual, 0.0);

  Eigen::Vector3d r_local;
  const ContactStatus local_status =
      solve_local_3d(problem.W, Eigen::Vector3d(problem.b), problem.mu[0], r_local);
  EXPECT_EQ(Eigen::Vector3d(r), r_local);
  ASSERT_EQ(status.size(), 1u);
  EXPECT_EQ(status[0], local_status);
  EXPECT_EQ(status[0], ContactStatus::slip);

  // 2D, sticking.
  FrictionContactProblem plane;
  plane.dimension = 2;
  plane.contacts = 1;
  plane.W.resize(2, 2);
  plane.W << 2.0, 0.5, 0.5, 1.0;
  plane.b = -plane.W * Eigen::Vector2d(1.0, 0.1);  // stick at r = (1, 0.1), inside μ = 0.5
  plane.mu = {Eigen::Vector2d(0.5, 0.0)};
  Eigen::VectorXd r2 = Eigen::VectorXd::Zero(2);
  const PgsStatistics plane_statistics = PgsSolver().solve(plane, r2, &status);
  EXPECT_TRUE(plane_statistics.converged);
  EXPECT_EQ(plane_statistics.iterations, 1);
  EXPECT_EQ(plane_statistics.residual, 0.0);
  EXPECT_LE(velocity(plane, r2).norm(), 1e-15);
  EXPECT_NEAR(r2(0), 1.0, 1e-15);
  EXPECT_NEAR(r2(1), 0.1, 1e-15);
  EXPECT_EQ(status[0], ContactStatus::stick);
}

TEST(PgsSolver, ASweepThatMovesOnlyTheFirstContactEndsTheSolve) {
  // Two uncoupled 3D contacts, the second warm-started at its solution: the sweep moves the first
  // alone, after which both are settled, and the solve stops there with a residual of exactly zero.
  // A second sweep would return the same impulses to the bit (checked by solving again from them).
  FrictionContactProblem problem;
  problem.dimension = 3;
  problem.contacts = 2;
  problem.W = Eigen::MatrixXd::Zero(6, 6);
  problem.W.topLeftCorner(3, 3) << 1.0, 0.1, -0.05, 0.1, 0.9, 0.2, -0.05, 0.2, 0.7;
  problem.W.bottomRightCorner(3, 3) << 2.0, 0.3, 0.0, 0.3, 1.5, 0.1, 0.0, 0.1, 1.2;
  problem.b.resize(6);
  problem.b << -1.0, 0.6, -0.4, -2.0, 0.1, 0.05;
  problem.mu = {Eigen::Vector2d(0.3, 0.2), Eigen::Vector2d(0.5, 0.5)};
  Eigen::Vector3d second;
  solve_local_3d(problem.W.bottomRightCorner(3, 3), problem.b.tail<3>(), problem.mu[1], second);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(6);
  r.tail<3>() = second;
  const PgsStatistics statistics = PgsSolver().solve(problem, r);
  EXPECT_TRUE(statistics.converged);
  EXPECT_EQ(statistics.iterations, 1);
  EXPECT_EQ(statistics.residual, 0.0);
  EXPECT_EQ(PgsSolver::residual(problem, r), 0.0);
  const Eigen::VectorXd once = r;
  const PgsStatistics again = PgsSolver().solve(problem, r);
  EXPECT_EQ(again.iterations, 1);
  EXPECT_EQ(r, once);

  // Coupled, the second contact moves too once the first has: no early stop, and the full residual
  // still decides.
  problem.W(0, 3) = problem.W(3, 0) = 0.2;
  r = Eigen::VectorXd::Zero(6);
  r.tail<3>() = second;
  const PgsStatistics coupled = PgsSolver().solve(problem, r);
  EXPECT_TRUE(coupled.converged);
  EXPECT_GT(coupled.iterations, 1);
  EXPECT_LE(PgsSolver::residual(problem, r), PgsParameters().tolerance);
}

TEST(PgsSolver, BoxPushedBelowThresholdSticks) {
  const BoxOnTwoCorners box;
  const FrictionContactProblem problem = box.problem(0.5 * box.mu * box.m * kGravity);
  Eigen::VectorXd r;
  const PgsStatistics statistics = PgsSolver().solve(problem, r);
  EXPECT_TRUE(statistics.converged);
  EXPECT_LE(statistics.residual, 1e-12);
  const Eigen::VectorXd u = velocity(problem, r);
  EXPECT_NEAR(u(1), 0.0, 1e-12);
  EXPECT_NEAR(u(3), 0.0, 1e-12);
  EXPECT_NEAR(u(0), 0.0, 1e-12);
  EXPECT_NEAR(u(2), 0.0, 1e-12);
  // Newton's second law on the box at rest: total impulses cancel gravity and the push.
  EXPECT_NEAR(r(0) + r(2), box.weight_impulse(), 1e-12);
  EXPECT_NEAR(r(1) + r(3), -0.5 * box.mu * box.weight_impulse(), 1e-12);
}

TEST(PgsSolver, BoxPushedAboveThresholdSlidesOnBothCorners) {
  const BoxOnTwoCorners box;
  const FrictionContactProblem problem = box.problem(2.0 * box.mu * box.m * kGravity);
  Eigen::VectorXd r;
  std::vector<ContactStatus> status;
  const PgsStatistics statistics = PgsSolver().solve(problem, r, &status);
  EXPECT_TRUE(statistics.converged);
  EXPECT_LE(statistics.residual, 1e-12);
  ASSERT_EQ(status.size(), 2u);
  EXPECT_EQ(status[0], ContactStatus::slip);
  EXPECT_EQ(status[1], ContactStatus::slip);
  const Eigen::VectorXd u = velocity(problem, r);
  EXPECT_GT(u(1), 0.0);
  EXPECT_GT(u(3), 0.0);
  const double normal_total = r(0) + r(2);
  const double tangential_total = r(1) + r(3);
  EXPECT_NEAR(tangential_total, -box.mu * normal_total, 1e-12 * box.mu * normal_total);
  // The push tilts the load to the front corner (corner 2 at +a): r_n2 − r_n1 = (b/a) μ·(weight).
  EXPECT_GT(r(2), r(0));
}

TEST(PgsSolver, BoxPushedExactlyAtThresholdSticksOnTheBoundary) {
  const BoxOnTwoCorners box;
  const FrictionContactProblem problem = box.problem(box.mu * box.m * kGravity);
  Eigen::VectorXd r;
  const PgsSolver solver;
  const PgsStatistics statistics = solver.solve(problem, r);
  EXPECT_TRUE(statistics.converged);
  EXPECT_LE(statistics.residual, solver.parameters().tolerance);
  const Eigen::VectorXd u = velocity(problem, r);
  EXPECT_LE(std::abs(u(1)), 1e-12);
  EXPECT_LE(std::abs(u(3)), 1e-12);
  // At the threshold the solution is unique: both corners on the cone, normal loads from the torque
  // balance a (r_n2 − r_n1) = b μ·(weight).
  const double weight = box.weight_impulse();
  EXPECT_NEAR(r(0), 0.5 * weight * (1 - box.b / box.a * box.mu), 1e-9 * weight);
  EXPECT_NEAR(r(2), 0.5 * weight * (1 + box.b / box.a * box.mu), 1e-9 * weight);
}

TEST(PgsSolver, BilateralConstraintWithUnidirectionalFriction) {
  // Point mass m on z = 0, frame (n, t1, t2) = (e_z, e_x, e_y), plus the bilateral row v_x − v_y = 0.
  // H rows: n (0,0,1), t1 (1,0,0), t2 (0,1,0), equality (1,−1,0); W = H Hᵀ / m. Free velocity: falling
  // at g h and sliding at V along (1,1,0)/√2. Friction μ = (0.1, 0) along x only. By hand:
  //   r_n = m g h, r_x = −μ1 r_n, r_y = 0, and v_x = v_y gives λ = −r_x / 2, so
  //   v_x = v_y = V/√2 − μ1 g h / 2, speed along the line V − μ1 g h cos45°.
  const double m = 3.0, V = 2.0, mu1 = 0.1;
  Eigen::Matrix<double, 4, 3> H;
  H << 0, 0, 1, 1, 0, 0, 0, 1, 0, 1, -1, 0;
  const Eigen::Vector3d v_free(V / std::sqrt(2.0), V / std::sqrt(2.0), -kGravity * kStep);
  FrictionContactProblem problem;
  problem.dimension = 3;
  problem.contacts = 1;
  problem.equalities = 1;
  problem.W = H * H.transpose() / m;
  problem.b = H * v_free;
  problem.mu = {Eigen::Vector2d(mu1, 0.0)};
  Eigen::VectorXd r;
  std::vector<ContactStatus> status;
  const PgsStatistics statistics = PgsSolver().solve(problem, r, &status);
  EXPECT_TRUE(statistics.converged);
  EXPECT_LE(statistics.residual, 1e-12);
  EXPECT_EQ(status[0], ContactStatus::slip);

  const Eigen::Vector3d v = v_free + H.transpose() * r / m;
  const double speed = (v(0) + v(1)) / std::sqrt(2.0);
  const double expected_speed = V - mu1 * kGravity * kStep * std::cos(M_PI / 4);
  EXPECT_NEAR(speed, expected_speed, 1e-10);
  EXPECT_NEAR(v(0) - v(1), 0.0, 1e-12);
  EXPECT_NEAR(v(2), 0.0, 1e-12);
  EXPECT_NEAR(r(0), m * kGravity * kStep, 1e-12);
  EXPECT_NEAR(r(1), -mu1 * m * kGravity * kStep, 1e-12);
  EXPECT_EQ(r(2), 0.0);
  EXPECT_NEAR(r(3), 0.5 * mu1 * m * kGravity * kStep, 1e-12);
}

TEST(PgsSolver, ALightNodeTiedToAHeavyBodySlidesWithItInOneSweep) {
  // A particle (mass m) on the ground, tied by three equality rows (v_p − v_B = 0) to a body of mass
  // M = 1e6 m; both slide at V and fall at g h in the step. Rows: contact n = y, t1 = x, t2 = z on the
  // particle; equalities H_e = [I, −I], whose impulse pushes the particle by r_e and the body by −r_e.
  // By hand, the pair slides as one mass: r_n = (m + M) g h, r_t1 = −μ r_n, both end at
  // (V − μ g h, 0, 0), and r_e = M (μ g h, −g h, 0). Alternating between the contact (W_cc = 1/m) and
  // the equality block (W_ee = 1/m + 1/M) contracts by M / (m + M) = 1 − 1e-6 a sweep; with the
  // equality rows condensed out the contact sees 1/(m + M) and one sweep solves it, no polish needed.
  // Tolerances: the velocities u = W r + q sum terms of 1/m · r_n ≈ 1e6 |q| to about |q|, so no r has
  // a full residual much below 1e-16 · 1e6 (7e-12 here), nor impulses closer than about 1e-10.
  const double m = 1e-6, M = 1.0, V = 2.0, mu = 0.3;
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  H(0, 1) = 1;  // n = y
  H(1, 0) = 1;  // t1 = x
  H(2, 2) = 1;  // t2 = z
  H.bottomLeftCorner<3, 3>().setIdentity();
  H.bottomRightCorner<3, 3>() = -Eigen::Matrix3d::Identity();
  Eigen::Matrix<double, 6, 1> M_inverse;
  M_inverse << 1 / m, 1 / m, 1 / m, 1 / M, 1 / M, 1 / M;
  Eigen::Matrix<double, 6, 1> v_free;
  v_free << V, -kGravity * kStep, 0, V, -kGravity * kStep, 0;
  FrictionContactProblem problem;
  problem.dimension = 3;
  problem.contacts = 1;
  problem.equalities = 3;
  problem.W = H * M_inverse.asDiagonal() * H.transpose();
  problem.b = H * v_free;
  problem.mu = {Eigen::Vector2d(mu, mu)};

  PgsParameters parameters;
  parameters.polish = false;
  parameters.max_iterations = 100;
  parameters.tolerance = 1e-10;
  Eigen::VectorXd r;
  const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r);
  ASSERT_TRUE(statistics.converged) << statistics.residual;
  EXPECT_LE(statistics.iterations, 3);
  const double r_n = (m + M) * kGravity * kStep, accuracy = 1e-9 * r_n;
  EXPECT_NEAR(r(0), r_n, accuracy);
  EXPECT_NEAR(r(1), -mu * r_n, accuracy);
  EXPECT_NEAR(r(2), 0.0, accuracy);
  EXPECT_NEAR(r(3), M * mu * kGravity * kStep, accuracy);
  EXPECT_NEAR(r(4), -M * kGravity * kStep, accuracy);
  EXPECT_NEAR(r(5), 0.0, accuracy);
  const Eigen::Matrix<double, 6, 1> v = v_free + M_inverse.asDiagonal() * (H.transpose() * r);
  EXPECT_NEAR(v(0), V - mu * kGravity * kStep, 1e-9);
  EXPECT_NEAR(v(3), V - mu * kGravity * kStep, 1e-9);
  EXPECT_NEAR(v(4), 0.0, 1e-9);
}

// A solver keeps its condensation of the equality rows while W is the same to the bit (a lumped
// World's steps): a new b then reuses it, a new W forms it again, and either way the impulses are the
// ones a fresh solver finds, to the bit (a stale condensation would give the last W's).
TEST(PgsSolver, ReusedCondensationGivesAFreshSolversImpulses) {
  Eigen::Matrix<double, 4, 3> H;
  H << 0, 0, 1, 1, 0, 0, 0, 1, 0, 1, -1, 0;
  FrictionContactProblem problem;
  problem.dimension = 3;
  problem.contacts = 1;
  problem.equalities = 1;
  problem.W = H * H.transpose() / 3.0;
  problem.b = H * Eigen::Vector3d(1.0, 1.5, -0.1);
  problem.mu = {Eigen::Vector2d(0.1, 0.2)};
  const PgsSolver kept;
  auto same_as_fresh = [&] {
    Eigen::VectorXd r, fresh;
    kept.solve(problem, r);
    PgsSolver().solve(problem, fresh);
    return r == fresh;
  };
  EXPECT_TRUE(same_as_fresh());
  problem.b = H * Eigen::Vector3d(-0.5, 2.0, -0.3);  // the same W
  EXPECT_TRUE(same_as_fresh());
  problem.W = H * H.transpose() / 7.0;  // a new W
  EXPECT_TRUE(same_as_fresh());
  problem.W(3, 3) *= 2.0;  // W_ee alone changes
  EXPECT_TRUE(same_as_fresh());
}

// A single equality row's W_ee⁺ x is written out: Eigen's LDLT solve to the bit, over signs and
// magnitudes, a singular (zero or subnormal) W_ee giving 0 as the pseudo-inverse does.
TEST(PgsSolver, SingleEqualitySolveIsTheLdltsToTheBit) {
  for (const double w : {2.5, -3.0, 1e-300, 3e-308, 1e-310, 0.0, -0.0, 7e300}) {
    for (const double b : {1.0, -0.3, 1e-200, 5e307, 0.0}) {
      PgsCondensation condensation;
      condensation.W_ee.compute(Eigen::MatrixXd::Constant(1, 1, w));
      Eigen::VectorXd x = Eigen::VectorXd::Constant(1, b);
      condensation.solve_equalities(x);
      const Eigen::VectorXd expected = condensation.W_ee.solve(Eigen::VectorXd::Constant(1, b));
      EXPECT_TRUE(x(0) == expected(0) && std::signbit(x(0)) == std::signbit(expected(0))) << w << ", " << b;
    }
  }
}

TEST(PgsSolver, EqualitiesOnlyAreSolvedInOneSweep) {
  FrictionContactProblem problem;
  problem.dimension = 3;
  problem.equalities = 2;
  problem.W.resize(2, 2);
  problem.W << 2.0, 0.5, 0.5, 1.0;
  problem.b = Eigen::Vector2d(1.0, -2.0);
  Eigen::VectorXd r;
  const PgsStatistics statistics = PgsSolver().solve(problem, r);
  EXPECT_TRUE(statistics.converged);
  EXPECT_LE(statistics.iterations, 2);
  EXPECT_LE(velocity(problem, r).norm(), 1e-14);
}

TEST(PgsSolver, ResidualVanishesAtSolutionAndNotElsewhere) {
  FrictionContactProblem problem;
  problem.dimension = 3;
  problem.contacts = 1;
  problem.W.resize(3, 3);
  problem.W << 1.0, 0.1, -0.05, 0.1, 0.9, 0.2, -0.05, 0.2, 0.7;
  problem.b = Eigen::Vector3d(-1.0, 0.6, -0.4);
  problem.mu = {Eigen::Vector2d(0.3, 0.3)};
  Eigen::Vector3d r_exact;
  solve_local_3d(problem.W, Eigen::Vector3d(problem.b), problem.mu[0], r_exact);
  EXPECT_LE(PgsSolver::residual(problem, r_exact), 1e-14);
  // r = 0 while the contact approaches: the whole normal velocity is unresolved.
  EXPECT_GT(PgsSolver::residual(problem, Eigen::VectorXd::Zero(3)), 0.5);
  // Right normal impulse, wrong friction: the residual sees the friction part too.
  Eigen::VectorXd frictionless = r_exact;
  frictionless(1) = frictionless(2) = 0.0;
  EXPECT_GT(PgsSolver::residual(problem, frictionless), 1e-3);

  // The box at the threshold, at the hand solution.
  const BoxOnTwoCorners box;
  const FrictionContactProblem box_problem = box.problem(box.mu * box.m * kGravity);
  const double weight = box.weight_impulse();
  Eigen::VectorXd r_box(4);
  r_box(0) = 0.5 * weight * (1 - box.b / box.a * box.mu);
  r_box(2) = 0.5 * weight * (1 + box.b / box.a * box.mu);
  r_box(1) = -box.mu * r_box(0);
  r_box(3) = -box.mu * r_box(2);
  EXPECT_LE(PgsSolver::residual(box_problem, r_box), 1e-14);
}

TEST(PgsSolver, ReportsNonConvergence) {
  const BoxOnTwoCorners box;
  const FrictionContactProblem problem = box.problem(2.0 * box.mu * box.m * kGravity);
  PgsParameters parameters;
  parameters.max_iterations = 1;
  parameters.polish = false;  // the Gauss–Seidel iteration's own reporting
  Eigen::VectorXd r;
  const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r);
  EXPECT_FALSE(statistics.converged);
  EXPECT_EQ(statistics.iterations, 1);
  EXPECT_GT(statistics.residual, parameters.tolerance);
  EXPECT_DOUBLE_EQ(statistics.residual, PgsSolver::residual(problem, r));
}

TEST(PgsSolver, SmallSweepIncrementAloneIsNotConvergence) {
  // Heavy under-relaxation makes every sweep move r by only 0.1 % of what is left: the cheap test passes
  // at a loose tolerance from the first sweep, but the full residual is still near 1 and must decide.
  FrictionContactProblem problem;
  problem.dimension = 3;
  problem.contacts = 1;
  problem.W = Eigen::Vector3d(1.0, 1.0, 1.0).asDiagonal();
  problem.b = Eigen::Vector3d(-1.0, 0.5, 0.0);
  problem.mu = {Eigen::Vector2d(0.3, 0.3)};
  PgsParameters parameters;
  parameters.omega = 1e-3;
  parameters.tolerance = 1e-2;
  parameters.max_iterations = 50;
  parameters.polish = false;  // the cheap test's logic alone
  Eigen::VectorXd r;
  const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r);
  EXPECT_FALSE(statistics.converged);
  EXPECT_EQ(statistics.iterations, 50);
  EXPECT_GT(statistics.residual, 0.5);
  EXPECT_DOUBLE_EQ(statistics.residual, PgsSolver::residual(problem, r));
}

// Right after a sweep, the residual skips the contacts whose term it knows to be zero (those after
// the last impulse that moved, dense_sweep.cpp's SweepResult): the residual reported must be the full
// one to the bit, with coupled contacts, over-relaxed sweeps (where the last moved impulse is not its
// local solution) and sweeps from nearly settled iterates alike.
TEST(PgsSolver, ResidualAfterASweepIsTheFullResidualToTheBit) {
  for (const int dimension : {2, 3}) {
    for (const double omega : {1.0, 1.3}) {
      const int contacts = 4, m = dimension * contacts, n = 7;
      Eigen::MatrixXd H(m, n);
      for (int i = 0; i < m; ++i)
        for (int j = 0; j < n; ++j) H(i, j) = std::sin(1.0 + 3.1 * i + 1.7 * j + 0.3 * i * j);
      FrictionContactProblem problem;
      problem.dimension = dimension;
      problem.contacts = contacts;
      problem.W = H * H.transpose();
      problem.b = H * Eigen::VectorXd::LinSpaced(n, -1.0, 0.5);
      problem.mu.assign(contacts, Eigen::Vector2d(0.3, 0.2));
      PgsParameters parameters;
      parameters.max_iterations = 1;  // one sweep a solve
      parameters.tolerance = 1e300;   // the cheap test passes: the residual follows the sweep
      parameters.omega = omega;
      parameters.polish = false;
      const PgsSolver one_sweep(parameters);
      Eigen::VectorXd r;
      int nonzero = 0;
      for (int sweep = 0; sweep < 60; ++sweep) {
        const PgsStatistics statistics = one_sweep.solve(problem, r);
        ASSERT_EQ(statistics.residual, PgsSolver::residual(problem, r))
            << "dimension " << dimension << ", omega " << omega << ", sweep " << sweep;
        nonzero += statistics.residual > 0.0;
      }
      EXPECT_GE(nonzero, 5);  // not only converged iterates
    }
  }
  // A contact whose local solve is rejected (not finite) is never taken as settled, even the last.
  const BoxOnTwoCorners box;
  FrictionContactProblem problem = box.problem(0.0);
  problem.W(2, 2) = std::numeric_limits<double>::quiet_NaN();
  PgsParameters parameters;
  parameters.max_iterations = 1;
  parameters.tolerance = 1e300;
  parameters.polish = false;
  Eigen::VectorXd r;
  const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r);
  EXPECT_EQ(statistics.rejected_local_solutions, 1);
  EXPECT_EQ(statistics.residual, std::numeric_limits<double>::infinity());
  EXPECT_FALSE(statistics.converged);
}

// A sweep's local problem at contact c sees b_c + Σ_{d≠c} W_cd r_d: the impulses of the contacts before
// it from this sweep, those after it from the last (dense_sweep.cpp, frozen_free_velocity). With every
// contact in stick (a wide cone, pressed), one sweep is block Gauss–Seidel written out here.
TEST(PgsSolver, ASweepIsBlockGaussSeidelOnTheOtherContactsImpulses) {
  for (const int dimension : {2, 3}) {
    const int contacts = 4, m = dimension * contacts, n = 9;
    Eigen::MatrixXd H(m, n);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < n; ++j) H(i, j) = std::sin(0.4 + 2.3 * i + 1.1 * j + 0.7 * i * j);
    FrictionContactProblem problem;
    problem.dimension = dimension;
    problem.contacts = contacts;
    problem.W = H * H.transpose();
    Eigen::VectorXd target = Eigen::VectorXd::Constant(m, 0.1);
    for (int c = 0; c < contacts; ++c) target(dimension * c) = 10.0 + c;
    problem.b = -problem.W * target;  // the solution: target, deep in its cones
    problem.mu.assign(contacts, Eigen::Vector2d(5.0, 5.0));
    PgsParameters parameters;
    parameters.max_iterations = 1;
    parameters.tolerance = 1e300;
    parameters.polish = false;
    Eigen::VectorXd start(m);
    for (int a = 0; a < m; ++a) start(a) = target(a) + 0.3 * std::cos(1.0 + 2.0 * a);
    Eigen::VectorXd r = start, expected = start;
    PgsSolver(parameters).solve(problem, r);
    for (int c = 0; c < contacts; ++c) {
      const int first = dimension * c;
      Eigen::VectorXd others = expected;
      others.segment(first, dimension).setZero();
      const Eigen::VectorXd b_c = problem.b.segment(first, dimension) + problem.W.middleRows(first, dimension) * others;
      expected.segment(first, dimension) =
          -problem.W.block(first, first, dimension, dimension).partialPivLu().solve(b_c);
    }
    EXPECT_LE((r - expected).norm(), 1e-11 * expected.norm()) << "dimension " << dimension;
    EXPECT_GT((r - target).norm(), 1e-3) << "one sweep, not the solution";
  }
}

TEST(PgsSolver, WarmStartFromSolutionTakesOneSweep) {
  const BoxOnTwoCorners box;
  for (const double push : {0.5, 2.0}) {
    const FrictionContactProblem problem = box.problem(push * box.mu * box.m * kGravity);
    Eigen::VectorXd r;
    const PgsStatistics cold = PgsSolver().solve(problem, r);
    ASSERT_TRUE(cold.converged);
    EXPECT_GT(cold.iterations, 2);
    const Eigen::VectorXd solution = r;
    const PgsStatistics warm = PgsSolver().solve(problem, r);
    EXPECT_TRUE(warm.converged);
    EXPECT_EQ(warm.iterations, 1);
    EXPECT_LE((r - solution).norm(), 1e-12 * solution.norm());
  }
}

TEST(PgsSolver, OverRelaxationReachesTheSameSolution) {
  const BoxOnTwoCorners box;
  const FrictionContactProblem problem = box.problem(2.0 * box.mu * box.m * kGravity);
  Eigen::VectorXd r_plain, r_relaxed;
  ASSERT_TRUE(PgsSolver().solve(problem, r_plain).converged);
  PgsParameters parameters;
  parameters.omega = 1.3;
  EXPECT_TRUE(PgsSolver(parameters).solve(problem, r_relaxed).converged);
  EXPECT_LE((r_relaxed - r_plain).norm(), 1e-10 * r_plain.norm());
}

TEST(PgsSolver, LiftedBoxIsOpen) {
  BoxOnTwoCorners box;
  FrictionContactProblem problem = box.problem(0.0);
  problem.b = -problem.b;  // moving up
  Eigen::VectorXd r = Eigen::VectorXd::Constant(4, 1.0);  // stale warm start
  std::vector<ContactStatus> status;
  const PgsStatistics statistics = PgsSolver().solve(problem, r, &status);
  EXPECT_TRUE(statistics.converged);
  EXPECT_EQ(r, Eigen::VectorXd::Zero(4));
  EXPECT_EQ(status, std::vector<ContactStatus>(2, ContactStatus::open));
}

TEST(PgsSolver, RejectsNonFiniteLocalSolutions) {
  const BoxOnTwoCorners box;
  FrictionContactProblem problem = box.problem(0.0);
  problem.b(1) = std::numeric_limits<double>::quiet_NaN();
  PgsParameters parameters;
  parameters.max_iterations = 5;
  Eigen::VectorXd r;
  const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r);
  EXPECT_FALSE(statistics.converged);
  EXPECT_EQ(statistics.rejected_local_solutions, 5);
  EXPECT_TRUE(r.allFinite());
  EXPECT_EQ(r(0), 0.0);  // the rejected contact kept its previous (zero) impulse
}

TEST(PgsSolver, InconsistentProblemThrows) {
  FrictionContactProblem problem;
  problem.contacts = 1;
  problem.W = Eigen::MatrixXd::Identity(2, 2);
  problem.b = Eigen::VectorXd::Zero(3);
  problem.mu = {Eigen::Vector2d(0.1, 0.1)};
  Eigen::VectorXd r;
  EXPECT_THROW(PgsSolver().solve(problem, r), std::invalid_argument);
}

}  // namespace
}  // namespace csim

namespace csim {
namespace {

// A body held by a weak spring and pressed on two contacts: W mixes a rigid-mode scale 1e7 times its
// elastic one. Gauss–Seidel alone stalls far from the tolerance; the active-set polish reaches it.
TEST(PgsSolver, ActiveSetPolishRescuesAnIllConditionedDelassus) {
  // Nine contacts along a block held by weak springs (as in SSNV503): its rigid modes (translation
  // across and along, rotation) dominate W by 1e7 over the elastic part, which sets the split.
  const int n = 9;
  FrictionContactProblem problem;
  problem.dimension = 2;
  problem.contacts = n;
  problem.mu.assign(n, Eigen::Vector2d(0.3, 0.3));
  Eigen::VectorXd across = Eigen::VectorXd::Zero(2 * n), along = across, turn = across;
  for (int i = 0; i < n; ++i) {
    across(2 * i) = 1.0;
    along(2 * i + 1) = 1.0;
    turn(2 * i) = (i - 4) / 4.0;
  }
  Eigen::MatrixXd W = 1e2 * (across * across.transpose() + along * along.transpose() + turn * turn.transpose());
  for (int i = 0; i < 2 * n; ++i) W(i, i) += 1e-5 * (1.0 + 0.1 * (i % 3));
  problem.W = W;
  problem.b = -1e4 * across + 1e3 * along + 1e-3 * turn;  // pressed, pushed well below the threshold
  PgsParameters plain;
  plain.polish = false;
  plain.max_iterations = 2000;
  plain.tolerance = 1e-10;
  Eigen::VectorXd r;
  const PgsStatistics gauss_seidel = PgsSolver(plain).solve(problem, r);
  PgsParameters polished = plain;
  polished.polish = true;
  Eigen::VectorXd r_polished;
  const PgsStatistics with_polish = PgsSolver(polished).solve(problem, r_polished);
  EXPECT_FALSE(gauss_seidel.converged) << gauss_seidel.residual;
  EXPECT_TRUE(with_polish.converged) << with_polish.residual;
  EXPECT_TRUE(with_polish.polished);
  EXPECT_LE(PgsSolver::residual(problem, r_polished), 1e-10);
  EXPECT_LT(with_polish.iterations, gauss_seidel.iterations);
}

TEST(PgsSolver, ActiveSetIterationFindsStickOnOneCornerAndSlipOnTheOther) {
  // Met in scenes/box-on-block (push 0.5 mu m g, at t = 0.055 s): a rigid box on two corners of a stiff
  // elastic block. The corners' tangential rows are coupled through the box almost rigidly: W has an
  // eigenvalue 9e-6 beside 0.17 to 0.63, so Gauss–Seidel needs about 2000 sweeps. The solution (from
  // enumerating the statuses) has corner 1 in stick and corner 2 in slip, which neither the statuses
  // of a stalled iterate nor "all closed in stick" give: the active-set correction must find it.
  FrictionContactProblem problem;
  problem.dimension = 2;
  problem.contacts = 2;
  problem.mu.assign(2, Eigen::Vector2d(0.3, 0.3));
  problem.W.resize(4, 4);
  problem.W << 0.3700077475627176, -0.09000001958016211, -0.16999879209819874, -0.09000057356748127,
      -0.09000001958016213, 0.13001686140186938, 0.09000055846082827, 0.1300095817980747,
      -0.1699987920981988, 0.09000055846082827, 0.37001057478270577, 0.09000010701182316,
      -0.09000057356748128, 0.1300095817980747, 0.09000010701182316, 0.13002023697636653;
  problem.b.resize(4);
  problem.b << -0.009890681765085136, -0.0014727323607641564, -0.009883155910741305, -0.0014736707597924324;
  PgsParameters parameters;
  parameters.max_iterations = 100;
  parameters.tolerance = 1e-12;
  Eigen::VectorXd r;
  std::vector<ContactStatus> status;
  const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r, &status);
  EXPECT_TRUE(statistics.converged) << statistics.residual;
  EXPECT_TRUE(statistics.polished);
  EXPECT_EQ(status[0], ContactStatus::stick);
  EXPECT_EQ(status[1], ContactStatus::slip);
  EXPECT_NEAR(r(3), 0.3 * r(2), 1e-14);  // on the cone, along +t
  const Eigen::VectorXd u = problem.W * r + problem.b;
  EXPECT_NEAR(u(1), 0.0, 1e-15);  // corner 1 sticks
  EXPECT_LT(u(3), 0.0);           // corner 2 slides against its friction
  PgsParameters plain = parameters;
  plain.polish = false;
  Eigen::VectorXd r_plain;
  EXPECT_FALSE(PgsSolver(plain).solve(problem, r_plain).converged);
}

TEST(PgsSolver, PolishFindsTheLateralSlipOfANodeHeldAcrossTheGround) {
  // Met in scenes/rolling-ring-3d on the benchmark's 34 x 5 mesh: a plane-strain HEXA8 ring (z held on
  // every node) under a cornering ground, 10 contacts. The ground slides laterally under the nodes
  // near x = 0 at 1e-7 of the step's rolling motion, and W's t2 column is zero there (nothing can move
  // them along z), so they must slip with u_t2 = q_t2 and a lateral friction of most of their cone.
  // The hub's free spin couples every t1 row (W_t1t1 = 100, nearly rank one), and Gauss–Seidel on
  // those steep slip laws stalls. The polish used to run Newton from the active set's result, which
  // had put these contacts in stick with r_t2 = 0 (its W_cc-weighted residual blind to r_t2): the
  // solve ended at 3.2e-7. From the Gauss–Seidel iterate Newton converges in a few steps.
  const FrictionContactProblem problem = test::problem_file("ring_cornering_lateral_slip_3d.txt");
  std::vector<int> held_across;  // contacts with a zero t2 column of W and a lateral free velocity
  for (int c = 0; c < problem.contacts; ++c)
    if (problem.W.col(3 * c + 2).norm() == 0.0 && problem.b(3 * c + 2) != 0.0) held_across.push_back(c);
  ASSERT_GE(held_across.size(), 2u);

  PgsParameters plain;
  plain.polish = false;
  plain.tolerance = 1e-10;
  plain.max_iterations = 20000;
  Eigen::VectorXd r_plain;
  EXPECT_GT(PgsSolver(plain).solve(problem, r_plain).residual, 1e-6);

  PgsParameters polished = plain;
  polished.polish = true;
  Eigen::VectorXd r;
  const PgsStatistics statistics = PgsSolver(polished).solve(problem, r);
  ASSERT_TRUE(statistics.converged) << statistics.residual;
  EXPECT_LE(statistics.iterations, 200);
  // Coulomb's slip law on the held contacts: r_t = −μ r_n u_t/|u_t|, with a lateral share of the cone.
  const Eigen::VectorXd u = problem.W * r + problem.b;
  int sliding_sideways = 0;
  for (const int c : held_across) {
    const double r_n = r(3 * c), mu = problem.mu[c](0);
    if (!(r_n > 1e-9 * r.maxCoeff())) continue;  // open (a round-off impulse)
    const Eigen::Vector2d u_t = u.segment<2>(3 * c + 1), r_t = r.segment<2>(3 * c + 1);
    EXPECT_EQ(u_t(1), problem.b(3 * c + 2));
    EXPECT_LE((r_t + mu * r_n * u_t.normalized()).norm(), 1e-6 * mu * r_n) << "contact " << c;
    if (std::abs(r_t(1)) > 0.5 * mu * r_n) ++sliding_sideways;
  }
  EXPECT_GE(sliding_sideways, 1);
}

// Met in scenes/rolling-ring-3d as a Moreau–Jean transient (theta 1, density 1e-3, at t = 1.01 s): six
// contacts of the ring tied to its hub, z held on every node, so that the contacts' t2 columns of the
// condensed W are zero. Reduced to its condensed contact rows (bit for bit what the condensation of the
// dumped 301-row problem gave) with each t2 row held by one equality row of stiffness a:
//   W = [S + a E Eᵀ, a E; a Eᵀ, a I], b = (b_condensed, 0),
// E selecting the t2 rows, which condenses back to S exactly. The polish at sweep 20 left the t2
// impulses 10 % outside their cones at a condensed residual of 1e-14, blind along those zero columns;
// the solve stopped there at a full residual of 1.3e-4 with its budget of 20000 sweeps unspent.
TEST(PgsSolver, CondensedIterationDecidesOnTheFullResidual) {
  const FrictionContactProblem problem = test::problem_file("ring_tied_hub_held_t2_3d.txt");
  ASSERT_EQ(problem.equalities, problem.contacts);
  PgsParameters parameters;
  parameters.tolerance = 1e-10;
  parameters.max_iterations = 20000;
  Eigen::VectorXd r;
  const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r);
  ASSERT_TRUE(statistics.converged) << statistics.residual << " after " << statistics.iterations << " sweeps";
  EXPECT_LE(PgsSolver::residual(problem, r), parameters.tolerance);
  // The law's impulse set (friction_contact_problem.h): each impulse in its cone, to round-off.
  const Eigen::VectorXd u = problem.W * r + problem.b;
  for (int c = 0; c < problem.contacts; ++c) {
    const double r_n = r(3 * c);
    const Eigen::Vector2d mu = problem.mu[c];
    EXPECT_GT(r_n, 0.0) << "contact " << c;  // every contact carries the ring's press
    EXPECT_LE(std::hypot(r(3 * c + 1) / mu(0), r(3 * c + 2) / mu(1)), (1.0 + 1e-9) * r_n) << "contact " << c;
  }
  // The held rows do not move (b_e = 0; a velocity scale of |b| = 11 m/s).
  EXPECT_LE(u.tail(problem.equalities).cwiseAbs().maxCoeff(), 1e-12 * problem.b.norm());
}

// The law is u = W r + b row by row; W need not be symmetric (pgs_solver.h). The hand check below reads
// W's rows only, so that no reading of its columns can pass it.
// Largest violation of the 2D Coulomb law at r, in velocity units: penetration, tension, complementarity
// (r_n u_n), friction outside its cone, a stick that slides, a slip that does not oppose its sliding.
double law_violation_2d(const FrictionContactProblem& problem, const Eigen::VectorXd& r) {
  const Eigen::VectorXd u = problem.W * r + problem.b;  // rows of W
  double worst = 0.0;
  for (int c = 0; c < problem.contacts; ++c) {
    const double r_n = r(2 * c), r_t = r(2 * c + 1), u_n = u(2 * c), u_t = u(2 * c + 1), mu = problem.mu[c](0);
    worst = std::max({worst, -u_n, -r_n, std::abs(r_n * u_n), std::abs(r_t) - mu * r_n});
    if (r_n > 0 && std::abs(r_t) < mu * r_n * (1 - 1e-9)) worst = std::max(worst, std::abs(u_t));  // stick
    if (r_n > 0 && std::abs(r_t) >= mu * r_n * (1 - 1e-9) && mu > 0) worst = std::max(worst, r_t * u_t);  // slip
  }
  return worst;
}

// Two frictionless contacts coupled one way: contact 1's normal velocity feels contact 2's impulse
// (W_n1n2 = 1/2), contact 2's does not feel contact 1's (W_n2n1 = 0). With b_n = (−1, −1) both close:
//   u_n1 = r_n1 + r_n2/2 − 1 = 0,  u_n2 = r_n2 − 1 = 0   ⇒   r_n = (1/2, 1),
// unique (W_nn is a P-matrix: its principal minors 1, 1, 1 are positive). Reading the coupling from
// W's columns instead solves Wᵀ: r_n = (1, 1/2), which leaves u_n1 = 0 and u_n2 = −1/2 (penetrating);
// the solver used to report that as converged, with a residual of 0 formed from the same columns.
FrictionContactProblem one_way_coupled_frictionless() {
  FrictionContactProblem problem;
  problem.dimension = 2;
  problem.contacts = 2;
  problem.W.resize(4, 4);
  problem.W << 1.0, 0.0, 0.5, 0.0,  //
      0.0, 1.0, 0.0, 0.0,           //
      0.0, 0.0, 1.0, 0.0,           //
      0.0, 0.0, 0.0, 1.0;
  problem.b.resize(4);
  problem.b << -1.0, 0.2, -1.0, -0.2;  // sliding both ways, frictionless: r_t = 0
  problem.mu.assign(2, Eigen::Vector2d(0.0, 0.0));
  return problem;
}

TEST(PgsSolver, SolvesAnUnsymmetricFrictionlessProblemByItsRows) {
  const FrictionContactProblem problem = one_way_coupled_frictionless();
  Eigen::VectorXd r;
  std::vector<ContactStatus> status;
  const PgsStatistics statistics = PgsSolver().solve(problem, r, &status);
  ASSERT_TRUE(statistics.converged) << statistics.residual;
  EXPECT_NEAR(r(0), 0.5, 1e-14);
  EXPECT_EQ(r(1), 0.0);
  EXPECT_NEAR(r(2), 1.0, 1e-14);
  EXPECT_EQ(r(3), 0.0);
  EXPECT_LE(law_violation_2d(problem, r), 1e-14);
  EXPECT_LE(statistics.residual, 1e-12);
  // The verdict is formed from W's rows: the columns' answer is far from converged.
  Eigen::VectorXd columns_answer(4);
  columns_answer << 1.0, 0.0, 0.5, 0.0;
  EXPECT_NEAR(law_violation_2d(problem, columns_answer), 0.5, 1e-15);  // u_n2 = −1/2
  EXPECT_GT(PgsSolver::residual(problem, columns_answer), 0.1);
  EXPECT_EQ(PgsSolver::residual(problem, r), statistics.residual);
}

// test::unsymmetric_frictional (test_problems.h): its solution, enumerated by hand, and that of Wᵀ.
TEST(PgsSolver, SolvesAnUnsymmetricFrictionalProblemByItsRows) {
  const FrictionContactProblem problem = test::unsymmetric_frictional();
  for (const bool polish : {true, false}) {
    PgsParameters parameters;
    parameters.polish = polish;
    Eigen::VectorXd r;
    std::vector<ContactStatus> status;
    const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r, &status);
    ASSERT_TRUE(statistics.converged) << "polish " << polish << ": " << statistics.residual;
    EXPECT_LE((r - Eigen::Vector4d(1.0, 0.1, 1.0, -0.3)).norm(), 1e-12) << "polish " << polish;
    EXPECT_EQ(status[0], ContactStatus::stick);
    EXPECT_EQ(status[1], ContactStatus::slip);
    EXPECT_LE(law_violation_2d(problem, r), 1e-12);
  }
  Eigen::VectorXd transposed_answer(4);
  transposed_answer << 2551.0 / 1660, -7653.0 / 16600, 13.0 / 83, -39.0 / 830;
  EXPECT_GT(PgsSolver::residual(problem, transposed_answer), 1e-2);
  // The polish alone (Newton and the active set read rows too) from a stalled start: one sweep, then
  // the final polish.
  PgsParameters one_sweep;
  one_sweep.max_iterations = 1;
  Eigen::VectorXd r;
  const PgsStatistics statistics = PgsSolver(one_sweep).solve(problem, r);
  ASSERT_TRUE(statistics.converged) << statistics.residual;
  EXPECT_TRUE(statistics.polished);
  EXPECT_LE((r - Eigen::Vector4d(1.0, 0.1, 1.0, -0.3)).norm(), 1e-12);
}

TEST(PgsSolver, SolvesAnUnsymmetricProblemWithAnEqualityRow) {
  // One frictional contact (μ = 0.3) and one bilateral row, W unsymmetric between them:
  //   rows n: (2, 1/2, 1), t: (0, 1, 1/2), e: (1/2, 0, 1), b = (−37/20, 0, −3/10).
  // Condensed (r_e = −(b_e + r_n/2)): W' = [[3/2, 1/2], [−1/4, 1]], b' = (−31/20, 3/20), whose only
  // solution (enumerated) is stick: r_c = (1, 1/10); then r_e = −(−3/10 + 1/2) = −1/5.
  FrictionContactProblem problem;
  problem.dimension = 2;
  problem.contacts = 1;
  problem.equalities = 1;
  problem.W.resize(3, 3);
  problem.W << 2.0, 0.5, 1.0,  //
      0.0, 1.0, 0.5,           //
      0.5, 0.0, 1.0;
  problem.b = Eigen::Vector3d(-37.0 / 20, 0.0, -0.3);
  problem.mu = {Eigen::Vector2d(0.3, 0.3)};
  const PgsSolver solver;
  for (int solve = 0; solve < 2; ++solve) {  // the second reuses the condensation
    Eigen::VectorXd r;
    const PgsStatistics statistics = solver.solve(problem, r);
    ASSERT_TRUE(statistics.converged) << statistics.residual;
    EXPECT_LE((r - Eigen::Vector3d(1.0, 0.1, -0.2)).norm(), 1e-14) << r.transpose();
    EXPECT_LE((problem.W * r + problem.b).norm(), 1e-14);  // stick and the equality: u = 0
  }
  // The columns' answer (Wᵀ's solution) is not taken for converged.
  FrictionContactProblem transposed = problem;
  transposed.W = problem.W.transpose();
  Eigen::VectorXd r_transposed;
  ASSERT_TRUE(PgsSolver().solve(transposed, r_transposed).converged);
  EXPECT_GT(PgsSolver::residual(problem, r_transposed), 1e-2);
}

// A 2D rigid box on three points of its bottom face (x = −a, 0, a): 6 rows for 3 freedoms, W of rank 3,
// a hyperstatic contact set whose impulses are not unique but whose resultant is. Pushed below the
// threshold it sticks: Σ r_n = m g h and Σ r_t = −F h. From one sweep the polish must finish it: its
// status systems are singular (no full pivoting: the proximal iteration), and so is Newton's Jacobian.
TEST(PgsSolver, PolishSolvesAHyperstaticBoxWithoutFullPivoting) {
  const double m = 2.0, a = 1.0, b = 0.5, I = m * (4 * a * a + 4 * b * b) / 12.0, mu = 0.3;
  Eigen::Matrix<double, 6, 3> H;
  H << 0, 1, -a, 1, 0, b,  // x = −a
      0, 1, 0, 1, 0, b,    // x = 0
      0, 1, a, 1, 0, b;    // x = a
  const Eigen::Matrix3d M_inverse = Eigen::Vector3d(1 / m, 1 / m, 1 / I).asDiagonal();
  for (const double push : {0.5 * mu * m * kGravity, 2.0 * mu * m * kGravity}) {
    FrictionContactProblem problem;
    problem.dimension = 2;
    problem.contacts = 3;
    problem.W = H * M_inverse * H.transpose();
    problem.b = H * Eigen::Vector3d(kStep * push / m, -kGravity * kStep, 0.0);
    problem.mu.assign(3, Eigen::Vector2d(mu, mu));
    PgsParameters parameters;
    parameters.max_iterations = 1;
    parameters.tolerance = 1e-12;
    Eigen::VectorXd r;
    const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r);
    ASSERT_TRUE(statistics.converged) << "push " << push << ": " << statistics.residual;
    EXPECT_TRUE(statistics.polished);
    EXPECT_GT(statistics.polish_factorizations, 0);
    const double weight = m * kGravity * kStep;
    EXPECT_NEAR(r(0) + r(2) + r(4), weight, 1e-10 * weight);
    EXPECT_NEAR(r(1) + r(3) + r(5), push < mu * m * kGravity ? -push * kStep : -mu * weight, 1e-10 * weight);
  }
}

// The box on four vertices of a stiff block needs the polish (Gauss–Seidel alone stays near 1e-6): its
// work stays within polish_budget times the sweeps' (no allowance here), and with none it does nothing.
TEST(PgsSolver, ThePolishStaysWithinItsBudget) {
  test::expect_polish_within_budget(test::problem_file("box_on_four_vertices_3d.txt"));
}

// Two frictionless contacts squeezing one freedom from both sides while both walls approach:
//   u_n1 = r_n1 − r_n2 − 1,  u_n2 = r_n2 − r_n1 − 1,
// whose sum is −2 whatever r: no impulses keep both contacts from penetrating, so nothing converges.
// Gauss–Seidel pushes both impulses up one a sweep; the polish runs at its schedule.
TEST(PgsSolver, NeverPolishesTwiceWithoutASweepBetween) {
  FrictionContactProblem problem;
  problem.dimension = 2;
  problem.contacts = 2;
  problem.W.resize(4, 4);
  problem.W << 1.0, 0.0, -1.0, 0.0,  //
      0.0, 1.0, 0.0, 0.0,            //
      -1.0, 0.0, 1.0, 0.0,           //
      0.0, 0.0, 0.0, 1.0;
  problem.b = Eigen::Vector4d(-1.0, 0.0, -1.0, 0.0);
  problem.mu.assign(2, Eigen::Vector2d(0.0, 0.0));
  // Polishes after sweep 20, every 200, and at the end unless the last one came after the last sweep.
  const std::vector<std::pair<int, int>> expected{{19, 1}, {20, 1}, {21, 2}, {200, 2}, {201, 3}, {400, 3}, {2000, 11}};
  for (const auto& [sweeps, polishes] : expected) {
    PgsParameters parameters;
    parameters.max_iterations = sweeps;
    Eigen::VectorXd r;
    const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r);
    EXPECT_FALSE(statistics.converged) << sweeps << " sweeps";
    EXPECT_GT(statistics.residual, 0.1) << sweeps << " sweeps";
    EXPECT_EQ(statistics.iterations, sweeps);
    EXPECT_EQ(statistics.polishes, polishes) << sweeps << " sweeps";
  }
  PgsParameters unpolished;
  unpolished.max_iterations = 200;
  unpolished.polish = false;
  Eigen::VectorXd r;
  EXPECT_EQ(PgsSolver(unpolished).solve(problem, r).polishes, 0);
}

// scenes/sdnv104-rigid with a 1 mg shoe (--set parameters.mass=1e-6 --set parameters.ramp_time=0), the
// problem of its second step (t = 0.002 s), which stopped the run: "contact solver failed … residual
// 1.4e-5 after 200 iterations". The shoe's free velocity is h N / m = 7e7 m/s downwards, so the step
// activates its four corners: the bottom ones (contacts 0, 1) and the top ones (2, 3), 1 m above the
// ground, whose gap term is g / (h θ) = 1 / (1e-3 · 0.5) = 2000 m/s. A corner's normal row is
// (0, 1, p_x): each top corner's is its bottom corner's, so u_n(top) = u_n(bottom) + 2000 m/s whatever
// the impulses, and the top corners must stay open. W's spectrum is 4e6 (the translation, 1/m) down to
// 667 (the rotation, held by the springs) and five zeros: Gauss–Seidel needs some 20000 sweeps, and
// the polish's status systems with a top and a bottom corner closed are inconsistent.
// By hand: the bottom corners hold the shoe (Σ r_n = h N = 70 N·s, the vertical having no stiffness),
// and it slides (the push, 200 kN, exceeds μ N = 21 kN): r_t = −μ r_n on each.
TEST(PgsSolver, SolvesARigidShoeWhoseTopCornersShareTheBottomOnesNormalRows) {
  const FrictionContactProblem problem = test::problem_file("sdnv104_rigid_1mg_shoe.txt");
  ASSERT_EQ(problem.contacts, 4);
  Eigen::VectorXd warm_start = Eigen::VectorXd::Zero(8);  // the run's: the first step's impulses
  warm_start.head(4) << 24.499999999986024, 7.3499999999958066, 45.500000000013976, 13.650000000004193;
  const double N_h = 70000.0 * 1e-3, mu = 0.3, top_gap_velocity = 1.0 / (1e-3 * 0.5);
  PgsParameters parameters;
  parameters.max_iterations = 200;  // the scene's contact_solver
  parameters.tolerance = 1e-12;
  for (const bool warm : {true, false}) {
    Eigen::VectorXd r = warm ? warm_start : Eigen::VectorXd::Zero(8);
    std::vector<ContactStatus> status;
    const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r, &status);
    ASSERT_TRUE(statistics.converged) << "warm " << warm << ": " << statistics.residual;
    EXPECT_LE(statistics.residual, 1e-12);
    const Eigen::VectorXd u = problem.W * r + problem.b;
    EXPECT_NEAR(r(0) + r(2), N_h, 1e-12 * N_h);
    for (const int bottom : {0, 1}) {
      EXPECT_EQ(status[bottom], ContactStatus::slip) << bottom;
      EXPECT_NEAR(r(2 * bottom + 1), -mu * r(2 * bottom), 1e-12 * N_h) << bottom;
      EXPECT_LE(std::abs(u(2 * bottom)), 1e-12 * problem.b.norm()) << bottom;
      EXPECT_GT(u(2 * bottom + 1), 0.0) << bottom;  // sliding along +t, against its friction
    }
    for (const int top : {2, 3}) {
      EXPECT_EQ(status[top], ContactStatus::open) << top;
      EXPECT_EQ(r(2 * top), 0.0);
      EXPECT_EQ(r(2 * top + 1), 0.0);
      EXPECT_NEAR(u(2 * top), top_gap_velocity, 1e-9 * problem.b.norm()) << top;
    }
  }
}

}  // namespace
}  // namespace csim
