#include "contact/pgs_solver.h"

#include "contact/dense_pgs.h"
#include "contact/dense_sweep.h"
#include "contact/pgs_iteration.h"
#include "contact/pgs_local.h"
#include "contact/sparse_pgs.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

// PgsSolver: the route to a path, and the dense path's iteration (pgs_iteration.h) on the pieces of
// dense_pgs.h's files.

namespace csim {
namespace dense_pgs {
namespace {

// A scheduled polish of the dense path is skipped when the sweeps, at the rate of the last ten, reach
// the tolerance within ten more sweeps, and tried again kFirstPolish sweeps later (pgs_iteration.h).
// On a few contacts a sweep costs a few local solves and a polish several factorizations and their
// local solves: Siconos' NESpheres_10_1 polished at sweep 20 for 65k instructions, about as many as
// its twenty sweeps. A slower rate than this predicts (a stack that settles its statuses late) costs
// at most kFirstPolish sweeps before the polish is tried again. With the window's ten sweeps, "the
// tolerance within ten sweeps at the rate newest/oldest per ten" is tolerance/newest ≥ newest/oldest:
// no pow or log (whose first call in a process costs more than a small solve: the dynamic linker).
// The dense path's pieces for the iteration (pgs_iteration.h): sweeps and residuals on W's rows, the
// polish of dense_polish.cpp on every schedule unless the sweeps are about to finish (above).
template <int D>
struct DensePath {
  const FrictionContactProblem& problem;
  const Eigen::MatrixXd& W_rows;
  const PgsParameters& parameters;
  pgs_local::ContractionWindow window{};

  double sweep_flops() const { return 2.0 * static_cast<double>(W_rows.size()); }
  SweepResult sweep(Eigen::VectorXd& r, int& rejected) const {
    return dense_pgs::sweep<D>(problem, W_rows, parameters, r, rejected);
  }
  double residual(const Eigen::VectorXd& r, int settled_from) const {
    return relative_residual(problem, W_rows, r, settled_from);
  }
  bool polish(Eigen::VectorXd& r, double& residual, PolishBudget& budget) const {
    return dense_pgs::polish<D>(problem, W_rows, r, residual, parameters.tolerance, budget);
  }
  void observe(const SweepResult& swept, double scale) { window.add(swept.increment_squared, scale); }
  bool stalled() const {
    const double newest = window.newest(), oldest = window.oldest();
    if (!(newest > 0.0) || !(newest < oldest)) return true;
    return !(parameters.tolerance * oldest >= newest * newest);
  }
  bool retries_skipped_polish() const { return true; }
};

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
  if (problem.dimension == 2) {
    DensePath<2> path{problem, W_rows, parameters};
    return pgs_local::iterate<2>(problem, parameters, path, r, status);
  }
  DensePath<3> path{problem, W_rows, parameters};
  return pgs_local::iterate<3>(problem, parameters, path, r, status);
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
