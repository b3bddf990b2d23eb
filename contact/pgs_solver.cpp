#include "contact/pgs_solver.h"

#include "contact/dense_pgs.h"
#include "contact/dense_sweep.h"
#include "contact/pgs_local.h"
#include "contact/sparse_pgs.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

// The iteration of the dense path: sweeps, the convergence tests and when to polish; the pieces are in
// dense_pgs.h's files.

namespace csim {
namespace dense_pgs {
namespace {

using pgs_local::status_of;
using pgs_local::velocity_scale;

// Sweeps between two attempts at the polish (dense_polish.cpp).
constexpr int kPolishInterval = 200;
// ... and once early, after 20 sweeps: when a few sweeps have sorted out the statuses, the direct
// solve finishes a problem that Gauss–Seidel would take hundreds of sweeps over (an ill-conditioned
// Delassus). A sweep costs 2 m² flops for m rows and an LU of the polish 2 m³/3, so the polish's budget
// (PgsParameters) lets it factor a few hundred rows at sweep 20 and more at later attempts.
constexpr int kFirstPolish = 20;

template <int D>
PgsStatistics solve_dimension(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows,
                              const PgsParameters& parameters, Eigen::VectorXd& r,
                              std::vector<ContactStatus>* status) {
  PgsStatistics statistics;
  // The sweep count at the last polish: the final polish is skipped when no sweep has run since the
  // last one. With max_iterations 20 or a multiple of 200 an unconverged solve used to polish twice in
  // a row, the second from the first one's result: twice the cost (23.9 s became 47.9 s on a
  // 296-contact problem) for at most a small gain (rolling-ring-3d-cornering, whose 7 unconverged
  // solves end at a relative residual of 3e-3 either way).
  int polished_after = -1;
  const auto polish_now = [&] {
    polished_after = statistics.iterations;
    PolishBudget budget = statistics.start_polish(parameters);
    statistics.finish_polish(budget, polish<D>(problem, W_rows, r, statistics.residual, parameters.tolerance, budget));
  };

  const double norm_b = problem.b.norm();
  bool residual_is_current = false;
  for (int iteration = 1; iteration <= parameters.max_iterations; ++iteration) {
    const SweepResult swept =
        sweep<D>(problem, W_rows, parameters, r, statistics.rejected_local_solutions);
    statistics.iterations = iteration;
    statistics.sweep_work += 2.0 * static_cast<double>(W_rows.size());
    residual_is_current = false;
    // A stalled iteration: try the active-set polish every kPolishInterval sweeps.
    if (parameters.polish && (iteration % kPolishInterval == 0 || iteration == kFirstPolish)) {
      statistics.residual = relative_residual(problem, W_rows, r, swept.settled_from);
      residual_is_current = true;
      polish_now();
      if (statistics.residual <= parameters.tolerance) {
        statistics.converged = true;
        break;
      }
      continue;
    }
    // Cheap test: a sweep that barely moved r, or one after which every contact is settled (the full
    // residual then costs no local solve, and the next sweep would return r to the bit: a single
    // contact is solved by its first sweep). Only then is the full residual (about one more sweep of
    // work) worth computing; it decides.
    const double scale = velocity_scale(norm_b, std::sqrt(swept.Wr_squared));
    if (swept.settled_from == 0 || std::sqrt(swept.increment_squared) <= parameters.tolerance * scale) {
      statistics.residual = relative_residual(problem, W_rows, r, swept.settled_from);
      residual_is_current = true;
      if (statistics.residual <= parameters.tolerance) {
        statistics.converged = true;
        break;
      }
    }
  }
  if (!residual_is_current) {
    statistics.residual = relative_residual(problem, W_rows, r);
    statistics.converged = statistics.residual <= parameters.tolerance;
  }
  if (parameters.polish && !statistics.converged && polished_after != statistics.iterations) {
    polish_now();
    statistics.converged = statistics.residual <= parameters.tolerance;
  }

  if (status != nullptr) {
    status->resize(problem.contacts);
    for (int c = 0; c < problem.contacts; ++c)
      (*status)[c] = status_of<D>(r.template segment<D>(static_cast<Eigen::Index>(D) * c), problem.mu[c]);
  }
  return statistics;
}

}  // namespace

PgsStatistics solve_contact_rows(const FrictionContactProblem& problem, const PgsParameters& parameters,
                                 Eigen::VectorXd& r, std::vector<ContactStatus>* status, Eigen::MatrixXd& transpose) {
  if (problem.contacts == 0) {
    if (status != nullptr) status->clear();
    PgsStatistics statistics;
    statistics.converged = true;
    return statistics;
  }
  const Eigen::MatrixXd& W_rows = rows_of(problem.W, transpose);
  return problem.dimension == 2 ? solve_dimension<2>(problem, W_rows, parameters, r, status)
                                : solve_dimension<3>(problem, W_rows, parameters, r, status);
}

}  // namespace dense_pgs

namespace {

void check_problem(const FrictionContactProblem& problem) {
  if (const std::string problem_with_it = inconsistency(problem); !problem_with_it.empty())
    throw std::invalid_argument("PgsSolver: " + problem_with_it);
}

// The route of a dense-stored W to the sparse path (pgs_solver.h): at least kSparseRouteRows rows and
// at most kSparseRouteDensity of its D × D blocks nonzero. The row count is tested first, so a small
// problem pays one comparison; the block count stops as soon as the limit is passed, so a full W pays
// a few columns' reads.
constexpr Eigen::Index kSparseRouteRows = 150;
constexpr double kSparseRouteDensity = 0.25;

bool sparse_enough(const FrictionContactProblem& problem) {
  const Eigen::Index m = problem.W.rows();
  if (problem.equalities > 0 || m < kSparseRouteRows) return false;
  const int D = problem.dimension;
  const double blocks = static_cast<double>(problem.contacts) * problem.contacts;
  const double limit = kSparseRouteDensity * blocks;
  double nonzero = 0.0;
  for (int j = 0; j < problem.contacts; ++j)
    for (int i = 0; i < problem.contacts; ++i)
      if (problem.W.block(static_cast<Eigen::Index>(D) * i, static_cast<Eigen::Index>(D) * j, D, D)
              .cwiseAbs().maxCoeff() != 0.0 && ++nonzero > limit)
        return false;
  return true;
}

}  // namespace

PgsStatistics PgsSolver::solve_routed(const FrictionContactProblem& problem, Eigen::VectorXd& r,
                                      std::vector<ContactStatus>* status) const {
  FrictionContactProblem& routed = scratch_.routed;
  routed.dimension = problem.dimension;
  routed.contacts = problem.contacts;
  routed.equalities = 0;
  routed.storage = DelassusStorage::sparse;
  routed.W_sparse = block_sparse(problem.W, problem.dimension);
  routed.b = problem.b;
  routed.mu = problem.mu;
  PgsStatistics statistics = solve_sparse(routed, parameters_, r, status, scratch_.completed);
  statistics.routed_to_sparse = true;
  return statistics;
}

namespace {

}  // namespace

PgsStatistics PgsSolver::solve(const FrictionContactProblem& problem, Eigen::VectorXd& r,
                               std::vector<ContactStatus>* status) const {
  check_problem(problem);
  // A warm start of the wrong size, or one carrying NaN/inf from an earlier failure, is worthless.
  if (r.size() != problem.size() || !r.allFinite()) r = Eigen::VectorXd::Zero(problem.size());
  if (problem.storage == DelassusStorage::sparse) return solve_sparse(problem, parameters_, r, status, scratch_.completed);
  if (parameters_.route_sparse && sparse_enough(problem)) return solve_routed(problem, r, status);
  if (problem.equalities > 0)
    return dense_pgs::solve_with_equalities(problem, parameters_, r, status, scratch_.condensation, scratch_.transpose);
  return dense_pgs::solve_contact_rows(problem, parameters_, r, status, scratch_.transpose);
}

double PgsSolver::residual(const FrictionContactProblem& problem, const Eigen::VectorXd& r) {
  check_problem(problem);
  if (r.size() != problem.size())
    throw std::invalid_argument("PgsSolver::residual: r has the wrong size");
  if (problem.size() == 0) return 0.0;
  if (problem.storage == DelassusStorage::sparse) return sparse_residual(problem, r);
  Eigen::MatrixXd transpose;
  return dense_pgs::relative_residual(problem, dense_pgs::rows_of(problem.W, transpose), r);
}

PolishBudget PgsStatistics::start_polish(const PgsParameters& parameters) {
  ++polishes;
  PolishBudget budget;
  budget.available = parameters.polish_budget * sweep_work + parameters.polish_allowance - polish_work;
  return budget;
}

void PgsStatistics::finish_polish(const PolishBudget& budget, bool improved) {
  polished = polished || improved;
  polish_work += budget.spent;
  polish_factorizations += budget.factorizations;
  polish_cut = polish_cut || budget.exhausted;
}

}  // namespace csim
