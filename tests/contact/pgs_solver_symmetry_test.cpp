// PgsSolver's dense path on a W symmetric to the bit, to round-off, and far from it (pgs_solver.h,
// contact/dense_pgs.h's symmetry_of): which reading of W's rows a solve used (PgsStatistics::
// near_symmetric_sweeps, transposed), and that each solve meets the tolerance on W's own rows.
// PgsSolver::residual is the yardstick: it reads W's rows from a copy of Wᵀ whenever W is not symmetric
// to the bit, independently of the solve's reading.
#include "contact/pgs_solver.h"
#include "contact/siconos_problem_format.h"

#include <gtest/gtest.h>

#include <fstream>

namespace csim {
namespace {

// Siconos' FrictionContactProblem00394 (2D, 6 contacts, W dense): its W is unsymmetric in a few
// entries by about 1e-17 of its largest (tests/contact/data/siconos/README.md).
FrictionContactProblem problem_00394() {
  std::ifstream in(CSIM_SOURCE_DIR "/tests/contact/data/siconos/FrictionContactProblem00394.dat");
  return read_siconos_problem(in);
}

TEST(PgsSolverSymmetry, SweepsANearSymmetricWOnItsOwnColumnsAndMeetsTheToleranceOnItsRows) {
  const FrictionContactProblem problem = problem_00394();
  const double skew = (problem.W - problem.W.transpose()).cwiseAbs().maxCoeff();
  ASSERT_GT(skew, 0.0);  // not symmetric to the bit: the case this path is for
  ASSERT_LE(skew, 1e-16 * problem.W.cwiseAbs().maxCoeff());
  const PgsSolver solver;
  Eigen::VectorXd r;
  const PgsStatistics statistics = solver.solve(problem, r);
  EXPECT_TRUE(statistics.converged);
  EXPECT_FALSE(statistics.transposed);
  EXPECT_EQ(statistics.near_symmetric_sweeps, statistics.iterations);
  EXPECT_GT(statistics.iterations, 0);
  EXPECT_LE(PgsSolver::residual(problem, r), solver.parameters().tolerance);
  // The residual the solve reports is W's own, up to the two formulas' round-off (1e-15 on a problem
  // of this size, far below the tolerance).
  EXPECT_NEAR(statistics.residual, PgsSolver::residual(problem, r), 1e-15);
}

TEST(PgsSolverSymmetry, ASymmetricWIsReadAsItIs) {
  FrictionContactProblem problem = problem_00394();
  problem.W = 0.5 * (problem.W + problem.W.transpose()).eval();
  ASSERT_TRUE(problem.W == problem.W.transpose());
  Eigen::VectorXd r;
  const PgsStatistics statistics = PgsSolver().solve(problem, r);
  EXPECT_TRUE(statistics.converged);
  EXPECT_FALSE(statistics.transposed);
  EXPECT_EQ(statistics.near_symmetric_sweeps, 0);
}

TEST(PgsSolverSymmetry, AWUnsymmetricAt1e3IsReadThroughItsTranspose) {
  FrictionContactProblem problem = problem_00394();
  const double largest = problem.W.cwiseAbs().maxCoeff();
  problem.W(2, 0) += 1e-3 * largest;
  problem.W(0, 4) -= 1e-3 * largest;
  const PgsSolver solver;
  Eigen::VectorXd r;
  const PgsStatistics statistics = solver.solve(problem, r);
  EXPECT_TRUE(statistics.converged);
  EXPECT_TRUE(statistics.transposed);
  EXPECT_EQ(statistics.near_symmetric_sweeps, 0);
  EXPECT_LE(PgsSolver::residual(problem, r), solver.parameters().tolerance);
}

// A W within the near-symmetry bound (skew s = 3e-15 against a largest diagonal entry of 1, below
// 16 ε ≈ 3.55e-15) whose skew matters because it multiplies a large impulse: 2D, μ = 0.5, tangential
// free velocities zero, W_cc = diag(1, 1) and diag(1e-6, 1e-6), b_n = −1 for both, and the only
// coupling W's entry (row 2, column 0) = s, contact 1's normal row reading contact 0's normal impulse.
// W's rows give, both contacts closed in stick with r_t = 0:
//   row 0: r_0 − 1 = 0                  → r_0 = 1,
//   row 2: s r_0 + 1e-6 r_2 − 1 = 0     → r_2 = (1 − s) · 1e6.
// Sweeps on W's columns read row 0 as (1, 0, s, 0) and row 2 as (0, 0, 1e-6, 0): their fixed point
// is r_2 = 1e6, r_0 = 1 − s · 1e6 = 1 − 3e-9, whose residual on W's rows is about 2e-9, far above the
// tolerance 1e-12. The solve must find that its near-symmetric sweeps have converged on their own
// problem, not on W's, and go on from there on Wᵀ.
constexpr double s = 3e-15;

FrictionContactProblem skew_on_a_large_impulse() {
  FrictionContactProblem problem;
  problem.dimension = 2;
  problem.contacts = 2;
  problem.W = Eigen::MatrixXd::Zero(4, 4);
  problem.W.diagonal() << 1.0, 1.0, 1e-6, 1e-6;
  problem.W(2, 0) = s;
  problem.b = Eigen::Vector4d(-1.0, 0.0, -1.0, 0.0);
  problem.mu = {Eigen::Vector2d(0.5, 0.5), Eigen::Vector2d(0.5, 0.5)};
  return problem;
}

TEST(PgsSolverSymmetry, FallsBackToTheTransposeWhenTheNearSymmetricAnswerMissesTheTolerance) {
  const FrictionContactProblem problem = skew_on_a_large_impulse();
  const PgsSolver solver;
  Eigen::VectorXd r;
  const PgsStatistics statistics = solver.solve(problem, r);
  EXPECT_TRUE(statistics.converged);
  EXPECT_TRUE(statistics.transposed);
  EXPECT_GT(statistics.near_symmetric_sweeps, 0);
  EXPECT_GT(statistics.iterations, statistics.near_symmetric_sweeps);
  EXPECT_LE(PgsSolver::residual(problem, r), solver.parameters().tolerance);
  // The hand solution above; the near-symmetric sweeps' answer was 3e-9 off in r_0.
  EXPECT_NEAR(r(0), 1.0, 1e-15);
  EXPECT_NEAR(r(2), (1.0 - s) * 1e6, 1e-9);
  EXPECT_EQ(r(1), 0.0);
  EXPECT_EQ(r(3), 0.0);
}

// The same with the polish off and a budget of sweeps that the near-symmetric sweeps use up: the
// exact path still runs (its sweeps counted on from theirs, within max_iterations) and converges.
TEST(PgsSolverSymmetry, FallsBackWithinTheSweepBudget) {
  const FrictionContactProblem problem = skew_on_a_large_impulse();
  PgsParameters parameters;
  parameters.polish = false;
  parameters.max_iterations = 6;
  Eigen::VectorXd r;
  const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r);
  EXPECT_TRUE(statistics.converged);
  EXPECT_LE(statistics.iterations, parameters.max_iterations);
  EXPECT_LE(PgsSolver::residual(problem, r), parameters.tolerance);
}

}  // namespace
}  // namespace csim
