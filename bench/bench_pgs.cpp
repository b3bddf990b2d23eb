// One Gauss–Seidel sweep of the frictional contact solver (contact/pgs_solver.h) against the number of
// contact rows (run by hand: build/bench/bench_pgs [repeats]). The problems are dense and coupled,
// W = H Hᵀ / n with a fixed H (n = m + 7 unknowns, entries sin(1 + 3.1 i + 1.7 j + 0.3 i j)), b = H x for a
// fixed x, μ = (0.3, 0.2): the shape of an FE body's Delassus operator, not its values. Each solve runs
// a fixed number of sweeps (tolerance 1e-300, no polish) from a zero warm start; the time a sweep is
// that of a solve over its sweeps, median of `repeats` solves [min–max], in µs. A sweep forms each
// contact's frozen free velocity (its D columns of W against r) and solves its local problem. The
// `sweeps` column gives how many ran: the smallest problems are solved to the bit before their count,
// and the full residuals that found it are in their time.
// Each problem is timed twice: W stored dense, and the same W stored sparse (every block stored: the
// sparse path's overhead where nothing is zero). A second table does the same on a chain of contacts
// (each coupled to its two neighbours, W block-tridiagonal): where the sparse path pays off.
#include "contact/pgs_solver.h"
#include "contact/sparse_pgs.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

csim::FrictionContactProblem coupled_problem(int dimension, int contacts) {
  const int m = dimension * contacts, n = m + 7;
  Eigen::MatrixXd H(m, n);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < n; ++j) H(i, j) = std::sin(1.0 + 3.1 * i + 1.7 * j + 0.3 * i * j);
  csim::FrictionContactProblem problem;
  problem.dimension = dimension;
  problem.contacts = contacts;
  problem.W = H * H.transpose() / n;
  problem.b = H * Eigen::VectorXd::LinSpaced(n, -1.0, 0.5);
  problem.mu.assign(contacts, Eigen::Vector2d(0.3, 0.2));
  return problem;
}

// Contacts in a chain, each coupled to its neighbours: W = H Hᵀ with H of bandwidth two contacts.
csim::FrictionContactProblem chain_problem(int dimension, int contacts) {
  const int m = dimension * contacts;
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = std::max(0, i - 2 * dimension + 1); j <= std::min(m - 1, i + 2 * dimension - 1); ++j)
      W(i, j) = (i == j ? 4.0 : 0.5 * std::sin(1.0 + i + j));
  csim::FrictionContactProblem problem;
  problem.dimension = dimension;
  problem.contacts = contacts;
  problem.W = 0.5 * (W + W.transpose());
  problem.b = Eigen::VectorXd::LinSpaced(m, -1.0, 0.5);
  problem.mu.assign(contacts, Eigen::Vector2d(0.3, 0.2));
  return problem;
}

csim::FrictionContactProblem as_sparse(const csim::FrictionContactProblem& dense) {
  csim::FrictionContactProblem sparse = dense;
  sparse.storage = csim::DelassusStorage::sparse;
  sparse.W_sparse = csim::block_sparse(dense.W, dense.dimension);
  sparse.W.resize(0, 0);
  return sparse;
}

// Median [min, max] of `repeats` solves' time a sweep, µs, and the sweeps of the last solve.
struct Timing {
  double median, low, high;
  int sweeps;
};

Timing time_sweeps(const csim::FrictionContactProblem& problem, int sweeps, int repeats) {
  csim::PgsParameters parameters;
  parameters.max_iterations = sweeps;
  parameters.tolerance = 1e-300;
  parameters.polish = false;
  const csim::PgsSolver solver(parameters);
  std::vector<double> per_sweep;
  int sweeps_done = 0;
  for (int k = 0; k < repeats; ++k) {
    Eigen::VectorXd r;
    const auto start = std::chrono::steady_clock::now();
    const csim::PgsStatistics statistics = solver.solve(problem, r);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    sweeps_done = statistics.iterations;
    per_sweep.push_back(1e6 * seconds / statistics.iterations);
  }
  std::sort(per_sweep.begin(), per_sweep.end());
  return {per_sweep[per_sweep.size() / 2], per_sweep.front(), per_sweep.back(), sweeps_done};
}

void table(const char* title, csim::FrictionContactProblem (*make)(int, int), int repeats) {
  std::printf("%s, median of %d solves [min-max], us a sweep\n", title, repeats);
  std::printf("%4s %8s %6s %7s %28s %28s %8s\n", "D", "contacts", "rows", "sweeps", "dense us [min-max]",
              "sparse us [min-max]", "stored");
  struct Case {
    int dimension, contacts, sweeps;
  };
  for (const Case c : {Case{2, 2, 400}, Case{3, 4, 400}, Case{2, 41, 40}, Case{3, 20, 40}, Case{2, 100, 20},
                       Case{3, 81, 20}, Case{3, 200, 5}, Case{3, 1000, 5}}) {
    if (c.contacts > 200 && make == coupled_problem) continue;
    const csim::FrictionContactProblem problem = make(c.dimension, c.contacts);
    const csim::FrictionContactProblem sparse = as_sparse(problem);
    // Alternating, so that the machine's drift is shared.
    const Timing dense_time = time_sweeps(problem, c.sweeps, repeats);
    const Timing sparse_time = time_sweeps(sparse, c.sweeps, repeats);
    std::printf("%4d %8d %6d %7d %10.3f [%.3f-%.3f] %10.3f [%.3f-%.3f] %7.1f%%\n", c.dimension, c.contacts,
                c.dimension * c.contacts, dense_time.sweeps, dense_time.median, dense_time.low, dense_time.high,
                sparse_time.median, sparse_time.low, sparse_time.high,
                100.0 * static_cast<double>(sparse.W_sparse.nonZeros()) / static_cast<double>(problem.W.size()));
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 15;
  table("Gauss-Seidel sweep on a dense coupled W", coupled_problem, repeats);
  table("Gauss-Seidel sweep on a chain (W block-tridiagonal)", chain_problem, repeats);
  return 0;
}
