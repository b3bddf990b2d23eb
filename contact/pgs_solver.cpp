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
//
// With `product` set, W is symmetric to round-off (symmetry_of) and W_rows is W itself: the sweeps read
// its columns as its rows, which spares the copy of Wᵀ (on Siconos' NESpheres_30_1, 44 contacts, skew
// 4e-17, 2 sweeps, the copy was 42 % of the solve's instructions). Those sweeps solve the problem
// whose off-diagonal rows are W's columns; every residual that decides convergence is W's own
// (relative_residual_by_columns, W r into *product), so a W whose skew matters is not declared
// converged on the wrong problem. When the sweeps have solved their own problem to the tolerance and
// W's residual is still above it (at_floor: more sweeps would not lower it), or the sweeps run out,
// the iteration stops without its final polish and the exact path (the copy) continues from the
// iterate (solve_contact_rows). The polish forms its systems from W's own rows and compares its
// candidates on the sweeps' residual; its result is then judged on W's. One path for both readings,
// so one instantiation of the iteration (the sweep inlined into it) per dimension, with the
// near-symmetric pieces out of line, so that the exact path inlined into the iteration stays as it was.
template <int D>
struct DensePath {
  const FrictionContactProblem& problem;
  const Eigen::MatrixXd& W_rows;
  const PgsParameters& parameters;
  Eigen::VectorXd* product = nullptr;  // near-symmetric reading: W r (the solver's work array)
  pgs_local::ContractionWindow window{};
  mutable bool floor = false;

  double sweep_flops() const { return 2.0 * static_cast<double>(W_rows.size()); }
  SweepResult sweep(Eigen::VectorXd& r, int& rejected) const {
    return dense_pgs::sweep<D>(problem, W_rows, parameters, r, rejected);
  }
  double residual(const Eigen::VectorXd& r, int settled_from) const {
    if (product != nullptr) [[unlikely]]
      return near_symmetric_residual(r, settled_from);
    return relative_residual(problem, W_rows, r, settled_from);
  }
  bool polish(Eigen::VectorXd& r, double& residual, PolishBudget& budget) const {
    if (product != nullptr) [[unlikely]]
      return near_symmetric_polish(r, residual, budget);
    return dense_pgs::polish<D>(problem, W_rows, r, residual, parameters.tolerance, budget);
  }
  // The near-symmetric reading's (above), out of line.
  [[gnu::noinline]] double near_symmetric_residual(const Eigen::VectorXd& r, int settled_from) const {
    const double own = relative_residual_by_columns(problem, r, *product);
    floor = own > parameters.tolerance && relative_residual(problem, W_rows, r, settled_from) <= parameters.tolerance;
    return own;
  }
  [[gnu::noinline]] bool near_symmetric_polish(Eigen::VectorXd& r, double& residual, PolishBudget& budget) const {
    double swept_residual = relative_residual(problem, W_rows, r);
    if (!dense_pgs::polish<D>(problem, W_rows, r, swept_residual, parameters.tolerance, budget)) return false;
    residual = near_symmetric_residual(r, problem.contacts);
    return true;
  }
  void observe(const SweepResult& swept, double scale) { window.add(swept.increment_squared, scale); }
  bool stalled() const {
    const double newest = window.newest(), oldest = window.oldest();
    if (!(newest > 0.0) || !(newest < oldest)) return true;
    return !(parameters.tolerance * oldest >= newest * newest);
  }
  bool retries_skipped_polish() const { return true; }
  bool at_floor() const { return floor; }
  bool gives_up() const { return false; }
  bool ends_with_polish() const { return product == nullptr; }
};

// The dense path on the condensed contact rows, whose convergence tests use the full problem's
// residual at the recovered r_e (pgs_solver.h). The condensed residual alone is blind along a zero
// column of the condensed W (a direction the ties hold, set exactly to zero by the condensation): its
// terms are W_cc (r_c − local_c(r)), so an impulse along that column outside the friction cone leaves
// them zero. The full residual weighs that direction by the full W_cc and sees it. On the tied 3D ring
// (rolling-ring-3d, Moreau–Jean, at t = 1.01 s) the polish at sweep 20 put the held t2 impulses of six
// contacts 10 % outside their cones at a condensed residual of 8e-15, and the solve stopped there with
// a full residual of 7e-5; the next sweep returns them to the cone (full residual 4e-11).
// The polish itself runs on the condensed rows, its candidates compared by the condensed residual.
// Once the condensed residual is at tolerance, the sweeps go on while the full residual falls: a test
// at which it does not fall ends the solve (at_floor), unconverged. The full residual then stands at
// its floor, the ties' cancellation (pgs_solver.h), which more sweeps of a converged condensed problem
// do not lower: on the plane rolling ring as a Moreau–Jean transient (tests/scenes: rolling-ring-
// moreau-jean) some solves end at 2e-10 against a tolerance of 1e-10, and went on to 20000 sweeps.
template <int D>
struct CondensedPath {
  DensePath<D> contacts;
  const FrictionContactProblem& problem;
  PgsCondensation& condensed;
  int& rejected;
  // The full residual at the last test whose condensed residual was at tolerance (infinite before).
  mutable double converged_condensed_full = std::numeric_limits<double>::infinity();
  mutable bool floor = false;

  double sweep_flops() const { return contacts.sweep_flops(); }
  SweepResult sweep(Eigen::VectorXd& r_c, int& rejected_in_sweep) const { return contacts.sweep(r_c, rejected_in_sweep); }
  double residual(const Eigen::VectorXd& r_c, int) const {
    const double full = recovered_residual(problem, condensed, r_c, condensed.full_r, rejected);
    if (full > contacts.parameters.tolerance &&
        contacts.residual(r_c, contacts.problem.contacts) <= contacts.parameters.tolerance) {
      floor = !(full < converged_condensed_full);
      converged_condensed_full = full;
    }
    return full;
  }
  bool at_floor() const { return floor; }
  bool gives_up() const { return false; }
  bool polish(Eigen::VectorXd& r_c, double& residual, PolishBudget& budget) const {
    double condensed_residual = contacts.residual(r_c, contacts.problem.contacts);
    if (!contacts.polish(r_c, condensed_residual, budget)) return false;
    residual = this->residual(r_c, 0);
    return true;
  }
  void observe(const SweepResult&, double) const {}
  bool stalled() const { return true; }
  bool retries_skipped_polish() const { return false; }
  bool ends_with_polish() const { return true; }
};

// The dense path on the contact rows of `problem`: W's rows read from W's columns (symmetric to the
// bit), from Wᵀ's (copied), or near-symmetric (DensePath with a product) and then, unless those sweeps
// converged on W's own residual, from Wᵀ's from their iterate, its sweeps and polish counted on from
// theirs. One call of the iteration, which the compiler inlines: with a second call site, for the
// copy after the near-symmetric sweeps, it did not, and a lumped scene's step cost more
// (bench/step_instructions.sh, docs/contact-problems.md).
template <int D>
[[gnu::always_inline]] inline PgsStatistics solve_rows(const FrictionContactProblem& problem,
                                                       const PgsParameters& parameters, Symmetry symmetry,
                         Eigen::VectorXd& r, std::vector<ContactStatus>* status, Eigen::MatrixXd& transpose,
                         Eigen::VectorXd& product) {
  PgsStatistics statistics;
  int polished_after = -1;
  for (;;) {
    if (symmetry == Symmetry::none) transpose.noalias() = problem.W.transpose();
    DensePath<D> path{problem, symmetry == Symmetry::none ? transpose : problem.W, parameters,
                      symmetry == Symmetry::near ? &product : nullptr};
    statistics = pgs_local::iterate<D>(problem, parameters, path, r, status, statistics, &polished_after);
    if (symmetry == Symmetry::none) statistics.transposed = true;
    if (symmetry != Symmetry::near) return statistics;
    statistics.near_symmetric_sweeps = statistics.iterations;
    if (statistics.converged) return statistics;
    symmetry = Symmetry::none;
  }
}

}  // namespace

PgsStatistics solve_condensed_rows(const FrictionContactProblem& problem, PgsCondensation& condensed,
                                   const PgsParameters& parameters, Eigen::VectorXd& r_c,
                                   std::vector<ContactStatus>* status, Eigen::MatrixXd& transpose) {
  const FrictionContactProblem& contacts = condensed.contacts;
  if (contacts.contacts == 0) return pgs_local::without_contacts(status);
  const Eigen::MatrixXd& W_rows = rows_of(contacts.W, transpose);
  const bool copied = &W_rows == &transpose;
  int rejected = 0;
  PgsStatistics statistics;
  if (contacts.dimension == 2) {
    CondensedPath<2> path{DensePath<2>{contacts, W_rows, parameters}, problem, condensed, rejected};
    statistics = pgs_local::iterate<2>(contacts, parameters, path, r_c, status);
  } else {
    CondensedPath<3> path{DensePath<3>{contacts, W_rows, parameters}, problem, condensed, rejected};
    statistics = pgs_local::iterate<3>(contacts, parameters, path, r_c, status);
  }
  statistics.transposed = copied;
  return statistics;
}

PgsStatistics solve_contact_rows(const FrictionContactProblem& problem, const PgsParameters& parameters,
                                 Eigen::VectorXd& r, std::vector<ContactStatus>* status, Eigen::MatrixXd& transpose,
                                 Eigen::VectorXd& product) {
  if (problem.contacts == 0) return pgs_local::without_contacts(status);
  const Symmetry symmetry = symmetry_of(problem.W);
  if (problem.dimension == 2) return solve_rows<2>(problem, parameters, symmetry, r, status, transpose, product);
  return solve_rows<3>(problem, parameters, symmetry, r, status, transpose, product);
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
  return dense_pgs::solve_contact_rows(problem, parameters_, r, status, scratch_.transpose, scratch_.product);
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

void PgsStatistics::add_work(const PgsStatistics& other) {
  rejected_local_solutions += other.rejected_local_solutions;
  polished = polished || other.polished;
  polishes += other.polishes;
  sweep_work += other.sweep_work;
  polish_work += other.polish_work;
  polish_factorizations += other.polish_factorizations;
  polish_cut = polish_cut || other.polish_cut;
  routed_to_sparse = routed_to_sparse || other.routed_to_sparse;
  near_symmetric_sweeps += other.near_symmetric_sweeps;
  transposed = transposed || other.transposed;
}

}  // namespace csim
