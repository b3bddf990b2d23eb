// One Gauss–Seidel sweep of the frictional contact solver (contact/pgs_solver.h) against the number of
// contact rows (run by hand: build/bench/bench_pgs [repeats]). The problems are dense and coupled,
// W = H Hᵀ / n with a fixed H (n = m + 7 unknowns, entries sin(1 + 3.1 i + 1.7 j + 0.3 i j)), b = H x for a
// fixed x, μ = (0.3, 0.2): the shape of an FE body's Delassus operator, not its values. Each solve runs
// a fixed number of sweeps (tolerance 1e-300, no polish) from a zero warm start; the time a sweep is
// that of a solve over its sweeps, median of `repeats` solves [min–max], in µs. A sweep forms each
// contact's frozen free velocity (its D columns of W against r) and solves its local problem. The
// `sweeps` column gives how many ran: the smallest problems are solved to the bit before their count,
// and the full residuals that found it are in their time.
#include "contact/pgs_solver.h"

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

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 15;
  std::printf("Gauss-Seidel sweep on a dense coupled W, median of %d solves [min-max], us a sweep\n", repeats);
  std::printf("%4s %8s %6s %7s %28s\n", "D", "contacts", "rows", "sweeps", "sweep us [min-max]");
  struct Case {
    int dimension, contacts, sweeps;
  };
  for (const Case c : {Case{2, 2, 400}, Case{3, 4, 400}, Case{2, 41, 40}, Case{3, 20, 40}, Case{2, 100, 20},
                       Case{3, 81, 20}, Case{3, 200, 5}}) {
    const csim::FrictionContactProblem problem = coupled_problem(c.dimension, c.contacts);
    csim::PgsParameters parameters;
    parameters.max_iterations = c.sweeps;
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
    std::printf("%4d %8d %6d %7d %10.3f [%.3f-%.3f]\n", c.dimension, c.contacts, c.dimension * c.contacts,
                sweeps_done, per_sweep[per_sweep.size() / 2], per_sweep.front(), per_sweep.back());
  }
  return 0;
}
