// A solve that stalls from its warm start is taken again from r = 0 (engine/contact_stage/contact_solve.h).
// The problem: one step of 8 spheres settling in a box (scenes/sphere-drop's generator, --count 8
// --seed 1, t = 0.49 s; 20 contacts, 60 rows, a hyperstatic frictional set), dumped with the warm start
// the step gave it (the previous impulses by contact key). From that start Gauss–Seidel and its polish
// stall above 1e-6 for 20 000 sweeps; from zero they converge.
// The second problem: 27 spheres (--count 27 --seed 1, t = 0.587 s; 64 contacts, 192 rows), where the
// polish stalls Gauss–Seidel from the warm start and from zero alike, and the sweeps alone converge.
#include "contact/pgs_solver.h"
#include "contact/sparse_pgs.h"
#include "engine/contact_stage/contact_solve.h"
#include "tests/contact/test_problems.h"

#include <gtest/gtest.h>

#include <fstream>

namespace csim {
namespace {

Vector warm_start_file(int size, const std::string& name = "settling_pile_8_spheres_3d_warm_start.txt") {
  std::ifstream file(CSIM_SOURCE_DIR "/tests/contact/data/" + name);
  std::vector<double> values;
  for (double value; file >> value;) values.push_back(value);
  EXPECT_EQ(static_cast<int>(values.size()), size);
  return Eigen::Map<const Vector>(values.data(), static_cast<Eigen::Index>(values.size()));
}

// The steps' settings of the scenes these problems come from: tolerance 1e-6, at most 20 000 sweeps.
PgsSolver settling_solver() {
  PgsParameters parameters;
  parameters.tolerance = 1e-6;
  parameters.max_iterations = 20000;
  return PgsSolver(parameters);
}

TEST(ContactSolve, ASolveThatStallsFromItsWarmStartIsTakenAgainFromZero) {
  const FrictionContactProblem problem = test::problem_file("settling_pile_8_spheres_3d.txt");
  const PgsSolver solver = settling_solver();

  // The premise: PgsSolver alone, from the warm start, does not converge.
  Vector warm = warm_start_file(problem.size());
  const PgsStatistics alone = solver.solve(problem, warm);
  ASSERT_FALSE(alone.converged) << alone.residual;
  ASSERT_GT(alone.residual, 1e-5);

  Vector r = warm_start_file(problem.size());
  std::vector<ActiveContact> active(problem.contacts);
  SolverCounters counters;
  const std::string failure = solve_contacts(solver, problem, 1e-6, 0.49, r, active, counters);
  EXPECT_EQ(failure, "");
  EXPECT_EQ(counters.cold_restarts, 1);
  EXPECT_EQ(counters.not_converged, 0);
  EXPECT_LE(PgsSolver::residual(problem, r), 1e-6);
  EXPECT_GT(counters.total_iterations, alone.iterations);  // the stalled solve's sweeps are counted
}

TEST(ContactSolve, ASolveThatThePolishStallsFromAnyStartIsTakenAgainBySweepsAlone) {
  const FrictionContactProblem problem = test::problem_file("settling_pile_27_spheres_3d.txt");
  const PgsSolver solver = settling_solver();
  const std::string start = "settling_pile_27_spheres_3d_warm_start.txt";

  // The premise: PgsSolver with its polish stalls above 1e-5 from the warm start and from zero.
  Vector warm = warm_start_file(problem.size(), start);
  ASSERT_GT(solver.solve(problem, warm).residual, 1e-5);
  Vector zero = Vector::Zero(problem.size());
  ASSERT_GT(solver.solve(problem, zero).residual, 1e-5);

  Vector r = warm_start_file(problem.size(), start);
  std::vector<ActiveContact> active(problem.contacts);
  SolverCounters counters;
  EXPECT_EQ(solve_contacts(solver, problem, 1e-6, 0.587, r, active, counters), "");
  EXPECT_EQ(counters.cold_restarts, 1);
  EXPECT_EQ(counters.sweeps_only_retries, 1);
  EXPECT_EQ(counters.not_converged, 0);
  EXPECT_LE(PgsSolver::residual(problem, r), 1e-6);
  EXPECT_GT(counters.total_iterations, 40000);  // the two stalled solves' sweeps are counted
}

// A sparse problem given with W's body-block factors (friction_contact_problem.h) whose solve does not
// converge is taken again with W stored dense, without the factors (the dense fallback, contact_solve.h).
// Two contacts of one body on the ground; one sweep cannot solve them.
TEST(ContactSolve, AnUnconvergedSolveWithBodyBlocksFallsBackToADenseW) {
  FrictionContactProblem problem;
  problem.dimension = 3;
  problem.contacts = 2;
  problem.storage = DelassusStorage::sparse;
  BodyBlockDelassus& blocks = problem.body_blocks;
  blocks.bodies = 1;
  blocks.body = {{0, -1}, {0, -1}};
  blocks.scaled_rows.assign(2 * 2 * 3 * BodyBlockDelassus::kBodySize, 0.0);
  Eigen::Matrix<double, 6, 6> K = Eigen::Matrix<double, 6, 6>::Zero();  // both contacts' rows, by rows
  K << 1, 0, 0, 0, 2, 0,  0, 1, 0, -2, 0, 0,  0, 0, 1, 0, 0, 0,
       1, 0, 0, 0, -2, 0,  0, 1, 0, 2, 0, 0,  0, 0, 1, 0, 0, 1;
  for (int c = 0; c < 2; ++c)
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 6; ++k) blocks.scaled_rows[(2 * c * 3 + i) * 6 + k] = K(3 * c + i, k);
  problem.W_sparse = block_sparse(K * K.transpose(), 3);
  problem.b = (Vector(6) << -1.0, 0.3, 0.2, -0.5, -0.2, 0.1).finished();
  problem.mu.assign(2, Eigen::Vector2d(0.5, 0.5));
  PgsParameters parameters;
  parameters.max_iterations = 1;
  parameters.polish = false;
  parameters.relax_sparse = false;
  const PgsSolver solver(parameters);
  Vector r = Vector::Zero(6);
  std::vector<ActiveContact> active(2);
  SolverCounters counters;
  std::string failure;
  ASSERT_NO_THROW(failure = solve_contacts(solver, problem, 1e300, 0.0, r, active, counters));
  EXPECT_EQ(failure, "");
  EXPECT_EQ(counters.dense_fallbacks, 1);
  EXPECT_EQ(counters.not_converged, 1);
  EXPECT_TRUE(r.allFinite());
}

}  // namespace
}  // namespace csim
