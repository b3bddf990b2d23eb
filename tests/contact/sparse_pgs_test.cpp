// The sparse path of PgsSolver (sparse_pgs.h) and its Newton polish (sparse_alart_curnier.h): the same
// impulses as the dense path, hyperstatic contact sets, unsymmetric W, the polish budget, the text format.
#include "contact/fclib_problem_format.h"
#include "contact/pgs_solver.h"
#include "contact/sparse_alart_curnier.h"
#include "contact/siconos_problem_format.h"
#include "contact/sparse_active_set.h"
#include "contact/sparse_pgs.h"
#include "tests/contact/test_problems.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace csim {
namespace {

using test::natural_map_error;
using test::problem_file;
using test::siconos_file;

constexpr double kGravity = 9.81;  // m/s²
constexpr double kStep = 0.01;     // s

FrictionContactProblem as_sparse(const FrictionContactProblem& dense) {
  FrictionContactProblem sparse = dense;
  sparse.storage = DelassusStorage::sparse;
  sparse.W_sparse = block_sparse(dense.W, dense.dimension);
  sparse.W.resize(0, 0);
  return sparse;
}

// A row of [dᵀ, (p × d)ᵀ] for a rigid body: the velocity of its point p (relative to the centre) along d.
Eigen::Matrix<double, 1, 6> rigid_row(const Eigen::Vector3d& p, const Eigen::Vector3d& d) {
  Eigen::Matrix<double, 1, 6> row;
  row << d.transpose(), p.cross(d).transpose();
  return row;
}

// Rigid bodies (mass m, inertia I about their centres) and contacts at points p_c of body A_c (and,
// unless B_c < 0, of body B_c at q_c), frame (n, t1, t2): W = H M⁻¹ Hᵀ, b = H v_free. Stored dense.
struct RigidScene {
  std::vector<Eigen::Matrix<double, 6, 1>> inverse_mass, free_velocity;
  struct Contact {
    int A, B;
    Eigen::Vector3d p, q, n, t1, t2;
  };
  std::vector<Contact> contacts;
  double mu = 0.3;

  FrictionContactProblem problem() const {
    const int bodies = static_cast<int>(inverse_mass.size());
    const int m = 3 * static_cast<int>(contacts.size());
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(m, 6 * bodies);
    Eigen::VectorXd M_inverse(6 * bodies), v(6 * bodies);
    for (int i = 0; i < bodies; ++i) {
      M_inverse.segment<6>(6 * i) = inverse_mass[i];
      v.segment<6>(6 * i) = free_velocity[i];
    }
    for (std::size_t c = 0; c < contacts.size(); ++c) {
      const Contact& k = contacts[c];
      const Eigen::Vector3d directions[3] = {k.n, k.t1, k.t2};
      for (int j = 0; j < 3; ++j) {
        // u = v_B − v_A: body B_c is pushed along n, body A_c (or the ground) away.
        H.block<1, 6>(3 * c + j, 6 * k.A) += rigid_row(k.p, directions[j]);
        if (k.B >= 0) H.block<1, 6>(3 * c + j, 6 * k.B) -= rigid_row(k.q, directions[j]);
      }
    }
    FrictionContactProblem problem;
    problem.dimension = 3;
    problem.contacts = static_cast<int>(contacts.size());
    problem.W = H * M_inverse.asDiagonal() * H.transpose();
    problem.b = H * v;
    problem.mu.assign(contacts.size(), Eigen::Vector2d(mu, mu));
    return problem;
  }
};

Eigen::Matrix<double, 6, 1> box_inverse_mass(double m, const Eigen::Vector3d& half) {
  const Eigen::Vector3d s = 4.0 * half.cwiseProduct(half);
  Eigen::Matrix<double, 6, 1> inverse;
  inverse << Eigen::Vector3d::Constant(1 / m), 12.0 / m / (s(1) + s(2)), 12.0 / m / (s(0) + s(2)),
      12.0 / m / (s(0) + s(1));
  return inverse;
}

// A box of half sizes (a, b, c) on the ground at `points` of its bottom face (z = −c), pushed along x by
// `push` (N) for one step under gravity: 3 × points rows for 6 freedoms, W of rank 6 at most.
RigidScene box_on_ground(const std::vector<Eigen::Vector2d>& points, double push, double m = 2.0) {
  const Eigen::Vector3d half(1.0, 0.5, 0.25);
  RigidScene scene;
  scene.inverse_mass = {box_inverse_mass(m, half)};
  Eigen::Matrix<double, 6, 1> v;
  v << kStep * push / m, 0, -kGravity * kStep, 0, 0, 0;
  scene.free_velocity = {v};
  for (const Eigen::Vector2d& xy : points)
    scene.contacts.push_back({0, -1, Eigen::Vector3d(xy(0), xy(1), -half(2)), Eigen::Vector3d::Zero(),
                              Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()});
  return scene;
}

std::vector<Eigen::Vector2d> four_corners() { return {{-1, -0.5}, {1, -0.5}, {1, 0.5}, {-1, 0.5}}; }
std::vector<Eigen::Vector2d> eight_points() {
  return {{-1, -0.5}, {0, -0.5}, {1, -0.5}, {1, 0}, {1, 0.5}, {0, 0.5}, {-1, 0.5}, {-1, 0}};
}

// A row of n balls (radius 0.1 m, 1 kg) on the ground, each touching the next; the first pushed toward
// the others along x and every ball spun a little: W block-tridiagonal, 3 (2n − 1) rows for 6n freedoms.
RigidScene row_of_balls(int n, double push) {
  const double R = 0.1, m = 1.0;
  RigidScene scene;
  Eigen::Matrix<double, 6, 1> inverse;
  inverse << Eigen::Vector3d::Constant(1 / m), Eigen::Vector3d::Constant(1 / (0.4 * m * R * R));
  for (int i = 0; i < n; ++i) {
    scene.inverse_mass.push_back(inverse);
    Eigen::Matrix<double, 6, 1> v;
    v << (i == 0 ? kStep * push / m : 0.0), 0.01 * (i % 3 - 1), -kGravity * kStep, 0.2 * ((i * 7) % 5 - 2), 0, 0;
    scene.free_velocity.push_back(v);
    scene.contacts.push_back({i, -1, Eigen::Vector3d(0, 0, -R), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(),
                              Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()});
    if (i + 1 < n)  // normal along −x pushes ball i + 1 ... body A = i + 1 at (−R, 0, 0), B = i at (R, 0, 0)
      scene.contacts.push_back({i + 1, i, Eigen::Vector3d(-R, 0, 0), Eigen::Vector3d(R, 0, 0), Eigen::Vector3d::UnitX(),
                                Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()});
  }
  return scene;
}

// Solves `dense` on both paths and checks that each result satisfies the law (the dense path's residual,
// computed from W's dense rows, judges the sparse result too) and, for a problem whose solution is
// unique (W positive definite, small μ), that the impulses agree. (With friction two solutions of the
// same problem may differ: the pushed row of balls has two at 1e-10, 3e-3 apart in u.)
void expect_same_solution(const FrictionContactProblem& dense, double tolerance, const std::string& name,
                          bool unique = false) {
  PgsParameters parameters;
  parameters.tolerance = tolerance;
  Eigen::VectorXd r_dense, r_sparse;
  const PgsStatistics on_dense = PgsSolver(parameters).solve(dense, r_dense);
  const FrictionContactProblem sparse = as_sparse(dense);
  const PgsStatistics on_sparse = PgsSolver(parameters).solve(sparse, r_sparse);
  ASSERT_TRUE(on_dense.converged) << name << ": dense " << on_dense.residual;
  ASSERT_TRUE(on_sparse.converged) << name << ": sparse " << on_sparse.residual;
  EXPECT_LE(PgsSolver::residual(dense, r_sparse), tolerance) << name;
  EXPECT_NEAR(PgsSolver::residual(sparse, r_sparse), PgsSolver::residual(dense, r_sparse), 1e-3 * tolerance) << name;
  if (unique) {
    EXPECT_LE((r_dense - r_sparse).norm(), 1e3 * tolerance * r_dense.norm()) << name;
  }
}

TEST(SparsePgs, SameImpulsesAsTheDensePathOnARowOfBalls) {
  for (const double push : {0.0, 3.0, 30.0}) {
    const FrictionContactProblem dense = row_of_balls(12, push).problem();
    expect_same_solution(dense, 1e-10, "balls, push " + std::to_string(push));
    // Blocks between contacts that share a ball: 23 diagonal ones, each ground contact with the two
    // ball–ball contacts of its ball (2 × 22 pairs, both ways) and consecutive ball–ball contacts
    // (10 pairs, both ways): 87 of 23² blocks.
    EXPECT_EQ(as_sparse(dense).W_sparse.nonZeros(), 9 * (23 + 2 * 22 + 2 * 10));
  }
}

TEST(SparsePgs, SameSolutionAsTheDensePathOnStoredProblems) {
  expect_same_solution(problem_file("box_on_four_vertices_3d.txt"), 1e-10, "box on four vertices", true);
  expect_same_solution(problem_file("ring_cornering_lateral_slip_3d.txt"), 1e-8, "ring cornering");
}

// A box on 4 (or 8) coplanar points: W has rank 6 for 12 (24) rows, the contact set is hyperstatic
// and the impulses are not unique; the resultant is. Pushed below μ m g it sticks: Σ r_n = m g h and
// Σ r_t1 = −F h; above, it slides: Σ r_t1 = −μ m g h.
TEST(SparsePgs, SolvesAHyperstaticBoxToTolerance) {
  const double m = 2.0, weight = m * kGravity * kStep;
  for (const auto& points : {four_corners(), eight_points()}) {
    for (const double push : {0.5 * 0.3 * m * kGravity, 2.0 * 0.3 * m * kGravity}) {
      const FrictionContactProblem problem = as_sparse(box_on_ground(points, push, m).problem());
      PgsParameters parameters;
      parameters.tolerance = 1e-12;
      Eigen::VectorXd r;
      const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r);
      ASSERT_TRUE(statistics.converged) << points.size() << " points, push " << push << ": " << statistics.residual;
      double normal = 0, tangent = 0, lateral = 0;
      for (int c = 0; c < problem.contacts; ++c) normal += r(3 * c), tangent += r(3 * c + 1), lateral += r(3 * c + 2);
      EXPECT_NEAR(normal, weight, 1e-9 * weight);
      EXPECT_NEAR(tangent, push < 0.3 * m * kGravity ? -push * kStep : -0.3 * weight, 1e-9 * weight);
      EXPECT_NEAR(lateral, 0.0, 1e-9 * weight);
    }
  }
}

// Newton alone on the hyperstatic box from r = 0: J's stick rows are W's (rank 6 of 12), and the
// proximal step finishes it; the sparse path has no dense factorization to fall back on.
TEST(SparseAlartCurnier, FinishesAHyperstaticBoxFromZeroByProximalSteps) {
  for (const auto& points : {four_corners(), eight_points()}) {
    const FrictionContactProblem problem = as_sparse(box_on_ground(points, 1.0).problem());
    Eigen::VectorXd r = Eigen::VectorXd::Zero(problem.size());
    PolishBudget budget;
    NewtonStatistics statistics;
    ASSERT_TRUE(sparse_alart_curnier_newton(problem, problem.W_sparse, r, 50, 1e-14, 1.0, budget, &statistics));
    EXPECT_LE(PgsSolver::residual(problem, r), 1e-12) << points.size() << " points, merit " << statistics.merit;
    EXPECT_GT(budget.factorizations, 0);
    EXPECT_GT(budget.regularized_steps, 0) << points.size() << " points: the plain step sufficed";
    EXPECT_FALSE(budget.exhausted);
  }
}

TEST(SparsePgs, SolvesAnUnsymmetricProblemByItsRows) {
  // test::unsymmetric_frictional, stored by blocks: its solution, found by enumerating the statuses in
  // exact arithmetic, is r = (1, 1/10, 1, −3/10); Wᵀ's would be both contacts slipping.
  const FrictionContactProblem problem = as_sparse(test::unsymmetric_frictional());
  for (const int sweeps : {2000, 1}) {  // 1: the polish alone finishes it
    PgsParameters parameters;
    parameters.max_iterations = sweeps;
    Eigen::VectorXd r;
    std::vector<ContactStatus> status;
    const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r, &status);
    ASSERT_TRUE(statistics.converged) << sweeps << ": " << statistics.residual;
    EXPECT_LE((r - Eigen::Vector4d(1.0, 0.1, 1.0, -0.3)).norm(), 1e-12);
    EXPECT_EQ(status[0], ContactStatus::stick);
    EXPECT_EQ(status[1], ContactStatus::slip);
  }
  Eigen::VectorXd transposed_answer(4);
  transposed_answer << 2551.0 / 1660, -7653.0 / 16600, 13.0 / 83, -39.0 / 830;
  EXPECT_GT(PgsSolver::residual(problem, transposed_answer), 1e-2);
}

// The box on four vertices of a stiff block needs the polish (Gauss–Seidel alone stays near 1e-6).
TEST(SparsePgs, ThePolishStaysWithinItsBudget) {
  const FrictionContactProblem problem = as_sparse(problem_file("box_on_four_vertices_3d.txt"));
  test::expect_polish_within_budget(problem);
  // The allowance alone (no sweep work to speak of: one sweep) is a bound too.
  PgsParameters one_sweep;
  one_sweep.max_iterations = 1;
  one_sweep.polish_budget = 0.0;
  one_sweep.polish_allowance = 5e4;
  Eigen::VectorXd r;
  const PgsStatistics statistics = PgsSolver(one_sweep).solve(problem, r);
  EXPECT_LE(statistics.polish_work, 5e4);
  EXPECT_TRUE(statistics.polish_cut);
}

// Siconos' Capsules-i125-1213 (FCLib, 286 contacts, W unsymmetric, J singular: every plain Newton step
// fails its factorization). From Gauss–Seidel's iterate at 200 sweeps (2.1e-6) the proximal steps
// with δ = ‖F‖ / scale left ‖F‖ where it was for 11 steps, and four polishes spent their whole budget
// (cut) before the sweeps finished at 803; with δ = √(‖F‖ / scale) (sparse_alart_curnier.h) Newton
// moves the iterate (2.1e-6 to 6.7e-7 in 30 steps) and the second polish finishes the solve, within
// its budget, long before Gauss–Seidel alone (2304 sweeps).
TEST(SparseAlartCurnier, MovesAnIterateWhereJIsSingular) {
  const FrictionContactProblem problem =
      read_fclib_problem(CSIM_SOURCE_DIR "/tests/contact/data/siconos/Capsules-i125-1213.hdf5");
  ASSERT_EQ(problem.storage, DelassusStorage::sparse);
  PgsParameters sweeps_only;
  sweeps_only.max_iterations = 200;
  sweeps_only.polish = false;
  sweeps_only.relax_sparse = false;  // Gauss–Seidel's own iterate (no relaxed attempt, sparse_pgs.h)
  Eigen::VectorXd r;
  PgsSolver(sweeps_only).solve(problem, r);
  const double start = PgsSolver::residual(problem, r);
  ASSERT_GT(start, 1e-6);
  PolishBudget budget;
  NewtonStatistics statistics;
  ASSERT_TRUE(sparse_alart_curnier_newton(problem, problem.W_sparse, r, 30, 1e-11, 1.0, budget, &statistics));
  EXPECT_GT(budget.regularized_steps, 0);
  EXPECT_LE(PgsSolver::residual(problem, r), 0.5 * start) << "from " << start;

  PgsParameters parameters;
  parameters.tolerance = 1e-8;
  parameters.max_iterations = 100000;
  Eigen::VectorXd solution;
  const PgsStatistics solved = PgsSolver(parameters).solve(problem, solution);
  ASSERT_TRUE(solved.converged) << solved.residual;
  EXPECT_LE(natural_map_error(problem, solution), 1e-8);
  EXPECT_FALSE(solved.polish_cut);
  EXPECT_LT(solved.iterations, 2304);
}

// The law is positively homogeneous: q scaled by s scales every solution r, and its u, by s. Siconos'
// 667-contact granular flow has ‖q‖ = 4.3e-18, below DBL_EPSILON, where Siconos' error turns absolute
// (bench_siconos.cpp): NSGS stops after one iteration at an absolute 3.7e-19, where the iterate is 0.09
// off the law relative to the problem's scale. csim's residual is relative: the same sweeps at both
// scales, q and q · 2^58 (a power of 2: exact), and the one-sweep iterate is no solution.
TEST(SparsePgs, ConvergenceIsRelativeToTheProblemsScale) {
  const FrictionContactProblem problem = siconos_file("fc2d_granularflowonwall_00667_00000.dat");
  ASSERT_LT(problem.b.norm(), 1e-17);
  FrictionContactProblem scaled = problem;
  const double scale = std::ldexp(1.0, 58);
  scaled.b *= scale;
  PgsParameters parameters;
  parameters.tolerance = 1e-8;
  parameters.max_iterations = 100000;
  Eigen::VectorXd r, r_scaled;
  const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r);
  const PgsStatistics scaled_statistics = PgsSolver(parameters).solve(scaled, r_scaled);
  ASSERT_TRUE(statistics.converged) << statistics.residual;
  ASSERT_TRUE(scaled_statistics.converged) << scaled_statistics.residual;
  EXPECT_EQ(statistics.iterations, scaled_statistics.iterations);
  EXPECT_NEAR(statistics.residual, scaled_statistics.residual, 1e-12);
  EXPECT_LE((scale * r - r_scaled).norm(), 1e-12 * r_scaled.norm());
  EXPECT_LE(natural_map_error(problem, r), 1e-8);
  EXPECT_LE(natural_map_error(scaled, r_scaled), 1e-8);

  PgsParameters one_sweep = parameters;
  one_sweep.max_iterations = 1;
  one_sweep.polish = false;
  Eigen::VectorXd r_one;
  PgsSolver(one_sweep).solve(problem, r_one);
  EXPECT_GT(natural_map_error(problem, r_one), 1e-2);
}

// Gauss–Seidel converging at a steady rate is not interrupted by the polish: Siconos' 00071 (89 contacts,
// 2D) takes 67 sweeps alone, its increments contracting by about 0.8 a sweep; polished at sweep 20 as the
// schedule says, it spent up to polish_budget × the sweeps' work in sparse LUs. The box on four vertices
// of a stiff block, where Gauss–Seidel stalls near 1e-6, is still polished and converges.
TEST(SparsePgs, PolishesOnlyAStalledIteration) {
  const FrictionContactProblem steady = siconos_file("FrictionContactProblem00071.dat");
  ASSERT_EQ(steady.storage, DelassusStorage::sparse);
  PgsParameters parameters;
  parameters.tolerance = 1e-8;
  parameters.max_iterations = 100000;
  Eigen::VectorXd r;
  const PgsStatistics statistics = PgsSolver(parameters).solve(steady, r);
  ASSERT_TRUE(statistics.converged) << statistics.residual;
  EXPECT_EQ(statistics.polishes, 0);
  EXPECT_GT(statistics.iterations, 20);  // past the first scheduled polish
  EXPECT_LE(natural_map_error(steady, r), 1e-8);

  const FrictionContactProblem stalled = as_sparse(problem_file("box_on_four_vertices_3d.txt"));
  parameters.tolerance = 1e-12;
  Eigen::VectorXd r_stalled;
  const PgsStatistics polished = PgsSolver(parameters).solve(stalled, r_stalled);
  ASSERT_TRUE(polished.converged) << polished.residual;
  EXPECT_GE(polished.polishes, 1);
  // The relaxed attempt's sweeps (at most 200, unpolished: sparse_pgs.h), then a polish within the
  // plain solve's first 200.
  EXPECT_LE(polished.iterations, 400);
  EXPECT_LE(natural_map_error(stalled, r_stalled), 1e-10);
}

// A stack of boxes (Siconos' BoxesStack1, 52 contacts, a hyperstatic set: four and more points per
// face): Gauss–Seidel stalls near 6e-4; Newton from its iterate took 62 sparse LUs over it, the
// active-set stage (sparse_active_set.h) 5, its statuses converging pass after pass. NSGS
// stops at 1.3e-6 of Siconos' natural map after 100000 iterations (docs/contact-problems.md).
TEST(SparseActiveSet, FinishesAStackOfBoxes) {
  const FrictionContactProblem problem = siconos_file("BoxesStack1-i100000-32.hdf5.dat");
  ASSERT_EQ(problem.storage, DelassusStorage::sparse);
  PgsParameters parameters;
  parameters.tolerance = 1e-8;
  parameters.max_iterations = 1000;
  Eigen::VectorXd r;
  const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r);
  ASSERT_TRUE(statistics.converged) << statistics.residual;
  EXPECT_LE(natural_map_error(problem, r), 1e-8);
  EXPECT_LE(statistics.polish_work, parameters.polish_budget * statistics.sweep_work + parameters.polish_allowance);

  // The stage alone from the Gauss–Seidel iterate's statuses: a solution of the statuses' system.
  PgsParameters sweeps_only = parameters;
  sweeps_only.polish = false;
  sweeps_only.max_iterations = 400;
  Eigen::VectorXd iterate;
  ASSERT_FALSE(PgsSolver(sweeps_only).solve(problem, iterate).converged);
  std::vector<ActiveSetStatus> statuses = statuses_of(problem, iterate, false);
  PolishBudget budget;
  Eigen::VectorXd candidate = iterate, next;
  for (int pass = 0; pass < 8; ++pass) {
    ASSERT_TRUE(solve_active_set(problem, problem.W_sparse, statuses, candidate, next, budget));
    candidate = next;
    if (!correct_statuses(problem, problem.W_sparse, candidate, statuses)) break;
  }
  EXPECT_LE(natural_map_error(problem, candidate), 1e-8);
  EXPECT_FALSE(budget.exhausted);
}

// A W stored dense but mostly zero blocks is solved on its block-sparse copy (PgsParameters::route_sparse):
// BoxesStack1 (52 contacts, 156 rows, 22 % of its 3 × 3 blocks nonzero) loaded dense takes the sparse
// path, and reaches the tolerance of the same residual (PgsSolver::residual on the dense problem) and the
// same natural-map error as the dense path (route_sparse false). A small dense problem keeps the dense path.
TEST(SparsePgs, RoutesADenseStoredBlockSparseProblem) {
  const FrictionContactProblem sparse = siconos_file("BoxesStack1-i100000-32.hdf5.dat");
  FrictionContactProblem dense = sparse;
  dense.storage = DelassusStorage::dense;
  dense.W = Eigen::MatrixXd(sparse.W_sparse);
  dense.W_sparse = SparseDelassus();
  PgsParameters parameters;
  parameters.tolerance = 1e-8;
  parameters.max_iterations = 1000;
  Eigen::VectorXd r_routed;
  const PgsStatistics routed = PgsSolver(parameters).solve(dense, r_routed);
  EXPECT_TRUE(routed.routed_to_sparse);
  ASSERT_TRUE(routed.converged) << routed.residual;
  EXPECT_LE(PgsSolver::residual(dense, r_routed), 1e-8);
  EXPECT_LE(natural_map_error(sparse, r_routed), 1e-8);  // the same operator, stored by blocks

  PgsParameters dense_only = parameters;
  dense_only.route_sparse = false;
  Eigen::VectorXd r_dense;
  const PgsStatistics kept = PgsSolver(dense_only).solve(dense, r_dense);
  EXPECT_FALSE(kept.routed_to_sparse);
  ASSERT_TRUE(kept.converged) << kept.residual;
  EXPECT_LE(PgsSolver::residual(dense, r_dense), 1e-8);
  EXPECT_LE(natural_map_error(sparse, r_dense), 1e-8);

  const FrictionContactProblem small = problem_file("box_on_four_vertices_3d.txt");
  ASSERT_EQ(small.storage, DelassusStorage::dense);
  Eigen::VectorXd r_small;
  EXPECT_FALSE(PgsSolver(parameters).solve(small, r_small).routed_to_sparse);
}

// A step of the packed 29-sphere box (bench/pile_scene.h: pile(29, 4, 4, 0.1), μ 0.5, steps of 1 ms):
// 90 contacts on 29 spheres (270 rows, 174 freedoms), a hyperstatic set, dumped from a run with its warm
// start (the previous step's impulses by contact key, zero for a new contact). Gauss–Seidel stalls (its
// relative increments stay near 2e-3 from sweep 100 to 700); the polish finishes it.
TEST(SparsePgs, SolvesAStepOfAPackedBoxOfSpheres) {
  const FrictionContactProblem problem = problem_file("packed_box_29_spheres_step_3d.txt");
  ASSERT_EQ(problem.storage, DelassusStorage::sparse);
  std::ifstream warm_file(CSIM_SOURCE_DIR "/tests/contact/data/packed_box_29_spheres_step_3d_warm_start.txt");
  std::vector<double> warm;
  for (double value; warm_file >> value;) warm.push_back(value);
  ASSERT_EQ(static_cast<int>(warm.size()), problem.size());
  Eigen::VectorXd r = Eigen::Map<const Eigen::VectorXd>(warm.data(), problem.size());
  PgsParameters parameters;
  parameters.tolerance = 1e-8;
  parameters.max_iterations = 20000;
  const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r);
  ASSERT_TRUE(statistics.converged) << statistics.residual;
  EXPECT_LE(natural_map_error(problem, r), 1e-8);
  EXPECT_GE(statistics.polishes, 1);
  EXPECT_LE(statistics.polish_work, parameters.polish_budget * statistics.sweep_work + parameters.polish_allowance);
}

TEST(SparsePgs, RefusesEqualityRowsByName) {
  FrictionContactProblem problem = as_sparse(problem_file("box_on_four_vertices_3d.txt"));
  const Eigen::Index n = problem.size();
  problem.equalities = 1;
  problem.W_sparse.conservativeResize(n + 1, n + 1);
  problem.W_sparse.insert(n, n) = 1.0;
  problem.b.conservativeResize(n + 1);
  problem.b(n) = 0.0;
  Eigen::VectorXd r;
  try {
    PgsSolver().solve(problem, r);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("store W dense"), std::string::npos) << error.what();
  }
}

TEST(SparsePgs, CompletesAPatternThatIsNotOfWholeBlocks) {
  // The balls' W with its stored zeros dropped and its rows left uncompressed: the solver completes a
  // copy and gives what the completed storage gives.
  const FrictionContactProblem dense = row_of_balls(5, 3.0).problem();
  FrictionContactProblem ragged = as_sparse(dense);
  ragged.W_sparse = dense.W.sparseView();
  ragged.W_sparse.uncompress();
  Eigen::VectorXd r_ragged, r_blocks;
  ASSERT_TRUE(PgsSolver().solve(ragged, r_ragged).converged);
  ASSERT_TRUE(PgsSolver().solve(as_sparse(dense), r_blocks).converged);
  EXPECT_LE((r_ragged - r_blocks).norm(), 1e-12 * r_blocks.norm());
}

TEST(FrictionContactProblemIo, SparseRoundTripsAndCompletesBlocks) {
  const FrictionContactProblem problem = as_sparse(row_of_balls(4, 3.0).problem());
  std::stringstream text;
  write_problem(text, problem);
  EXPECT_NE(text.str().find("W sparse " + std::to_string(problem.W_sparse.nonZeros())), std::string::npos);
  const FrictionContactProblem read = read_problem(text);
  ASSERT_EQ(read.storage, DelassusStorage::sparse);
  EXPECT_EQ(read.W.size(), 0);
  EXPECT_EQ(read.W_sparse.nonZeros(), problem.W_sparse.nonZeros());
  EXPECT_EQ((Eigen::MatrixXd(read.W_sparse) - Eigen::MatrixXd(problem.W_sparse)).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(read.b, problem.b);
  // One entry of a 2 × 2 block between contacts 0 and 1 stands for the whole block.
  std::istringstream partial(
      "csim-friction-contact-problem 1\ndimension 2\ncontacts 2\nequalities 0\nmu\n0.3 0.3\n0.3 0.3\n"
      "q\n-1 0 -1 0\nW sparse 5\n0 0 1\n1 1 1\n2 2 1\n3 3 1\n0 3 0.5\nend\n");
  const FrictionContactProblem completed = read_problem(partial);
  EXPECT_EQ(completed.W_sparse.nonZeros(), 12);  // blocks (0, 0), (0, 1), (1, 1)
  EXPECT_EQ(completed.W_sparse.coeff(0, 3), 0.5);
  std::istringstream outside(
      "csim-friction-contact-problem 1\ndimension 2\ncontacts 1\nequalities 0\nmu\n0.3 0.3\nq\n-1 0\nW sparse 1\n"
      "0 2 1\nend\n");
  EXPECT_THROW(read_problem(outside), std::runtime_error);
}

}  // namespace
}  // namespace csim
