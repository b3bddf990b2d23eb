// How accurately a problem file determines its own solution: for one Siconos text file, the error a
// solver stalls at against what the printed precision of W leaves undetermined (docs/contact-problems.md,
// "Problems not solved").
//
//   bench_data_floor FILE [--digits 6] [--sweeps 2000] [--eigenvalues]
//
// 1. The stall: csim's Gauss–Seidel (polish off) for --sweeps sweeps, then 10 Alart–Curnier Newton
//    steps (sparse_alart_curnier.h, no budget) at each ρ scale 1e-2, 1, 1e2; Siconos' natural-map
//    error (fc2d/fc3d_compute_error, the yardstick of bench_siconos) after each.
// 2. The data's floor: W as printed with --digits significant digits stands for every W whose entries
//    lie within half a unit of the last digit. The bound Σ_j ½ulp(W_ij) |r_j| on W r, relative to
//    max(‖q‖, ‖r‖, ‖u‖), and csim's residual (pgs_solver.h) of the same r on five such W (symmetric
//    pairs moved alike, a fixed pseudo-random sequence): the part of the residual the file cannot decide.
// 3. --eigenvalues: the extreme eigenvalues of W's symmetric part and how many are negative (dense,
//    O(m³): minutes for m = 4000), and how many are zero to 1e-10 of the largest (a hyperstatic set's).
#include "contact/friction_contact_problem.h"
#include "contact/pgs_solver.h"
#include "contact/siconos_problem_format.h"
#include "contact/sparse_alart_curnier.h"
#include "contact/sparse_pgs.h"
#include "bench/siconos_error.h"

#include <FrictionContactProblem.h>
#include <NumericsMatrix.h>
#include <SparseBlockMatrix.h>
#define restrict __restrict  // fc2d_compute_error.h is C99
#include <fc2d_compute_error.h>
#undef restrict
#include <fc3d_compute_error.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace {

// Half a unit in the last printed digit of w (digits significant digits).
double half_unit(double w, int digits) {
  return w == 0.0 ? 0.0 : 0.5 * std::pow(10.0, std::floor(std::log10(std::abs(w))) - (digits - 1));
}

// A number in [−1, 1] fixed by the unordered pair (i, j) and the trial (splitmix64).
double pair_sign(int i, int j, int trial) {
  std::uint64_t h = static_cast<std::uint64_t>(std::min(i, j)) * 1000003u + static_cast<std::uint64_t>(std::max(i, j)) +
                    0x9e3779b97f4a7c15ull * static_cast<std::uint64_t>(trial + 1);
  h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
  h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
  h ^= h >> 31;
  return 2.0 * static_cast<double>(h % 1000001u) / 1e6 - 1.0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_data_floor FILE [--digits 6] [--sweeps 2000] [--eigenvalues]\n");
    return 2;
  }
  const std::string path = argv[1];
  int digits = 6, sweeps = 2000;
  bool eigenvalues = false;
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--digits") && i + 1 < argc) digits = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--sweeps") && i + 1 < argc) sweeps = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--eigenvalues")) eigenvalues = true;
  }
  std::ifstream in(path);
  csim::FrictionContactProblem problem = csim::read_siconos_problem(in);
  if (problem.storage != csim::DelassusStorage::sparse) {
    problem.W_sparse = csim::block_sparse(problem.W, problem.dimension);
    problem.W.resize(0, 0);
    problem.storage = csim::DelassusStorage::sparse;
  }
  FILE* file = std::fopen(path.c_str(), "r");
  ::FrictionContactProblem* theirs = frictionContact_newFromFile(file);
  std::fclose(file);
  std::printf("%s: d %d, %d contacts, W printed with %d digits (as given)\n", path.c_str(), problem.dimension,
              problem.contacts, digits);

  csim::PgsParameters parameters;
  parameters.tolerance = 1e-8;
  parameters.max_iterations = sweeps;
  parameters.polish = false;
  Eigen::VectorXd start = Eigen::VectorXd::Zero(problem.size());
  csim::PgsSolver(parameters).solve(problem, start);
  std::printf("Gauss–Seidel, %d sweeps: error %.3e\n", sweeps, csim::bench::siconos_error(*theirs, start, 1e-8));
  Eigen::VectorXd r = start;
  for (const double rho_scale : {1e-2, 1.0, 1e2}) {
    Eigen::VectorXd candidate = start;
    csim::PolishBudget budget;
    csim::NewtonStatistics newton;
    csim::sparse_alart_curnier_newton(problem, problem.W_sparse, candidate, 10, 1e-14, rho_scale, budget, &newton);
    std::printf("Newton at ρ scale %g: %d steps, error %.3e\n", rho_scale, newton.iterations,
                csim::bench::siconos_error(*theirs, candidate, 1e-8));
    if (rho_scale == 1.0) r = candidate;
  }

  const csim::SparseDelassus W = problem.W_sparse;
  const Eigen::VectorXd u = W * r + problem.b;
  const double scale = std::max({problem.b.norm(), r.norm(), u.norm()});
  Eigen::VectorXd bound = Eigen::VectorXd::Zero(problem.size());
  for (int i = 0; i < W.outerSize(); ++i)
    for (csim::SparseDelassus::InnerIterator it(W, i); it; ++it)
      bound(i) += half_unit(it.value(), digits) * std::abs(r(it.col()));
  std::printf("at Newton's (ρ scale 1) iterate: csim residual %.3e; printed precision: ‖Σ½ulp|r|‖ / max(‖q‖,‖r‖,‖u‖) = %.3e\n",
              csim::sparse_residual(problem, r), bound.norm() / scale);
  for (int trial = 0; trial < 5; ++trial) {
    csim::FrictionContactProblem moved = problem;
    for (int i = 0; i < W.outerSize(); ++i)
      for (csim::SparseDelassus::InnerIterator it(moved.W_sparse, i); it; ++it)
        it.valueRef() += half_unit(it.value(), digits) * pair_sign(i, static_cast<int>(it.col()), trial);
    std::printf("  the same r on a W within the printed digits (%d): csim residual %.3e\n", trial + 1,
                csim::sparse_residual(moved, r));
  }
  if (eigenvalues) {
    const Eigen::MatrixXd dense = Eigen::MatrixXd(W);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(0.5 * (dense + dense.transpose()),
                                                                Eigen::EigenvaluesOnly);
    const Eigen::VectorXd& lambda = solver.eigenvalues();
    const double largest = lambda(lambda.size() - 1);
    const long negative = (lambda.array() < 0.0).count();
    const long null = (lambda.array().abs() <= 1e-10 * largest).count();
    std::printf("symmetric part of W: eigenvalues %.3e to %.3e, %ld negative, %ld zero (|λ| ≤ 1e-10 of the largest)\n",
                lambda(0), largest, negative, null);
  }
  return 0;
}
