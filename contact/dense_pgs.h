// The pieces of PgsSolver's dense path (pgs_solver.h states the method), one job a file:
//   dense_sweep.h, .cpp        a Gauss–Seidel sweep and the full residual on a dense W, read by rows;
//   active_set_polish.cpp      the active-set iteration on the statuses' linear systems;
//   dense_polish.cpp           the polish: the active set, then Newton (alart_curnier.h), within a budget;
//   equality_condensation.cpp  the bilateral rows condensed out before the sweeps;
//   pgs_iteration.h            the iteration both paths share: sweeps, convergence tests, when to polish;
//   pgs_solver.cpp             the dense path that runs it on these pieces.
// Internal to contact/.
#pragma once

#include "contact/pgs_local.h"
#include "contact/pgs_solver.h"
#include "contact/polish_budget.h"

#include <Eigen/Dense>
#include <vector>

namespace csim::dense_pgs {

// True if W equals its transpose to the bit.
bool is_symmetric(const Eigen::MatrixXd& W);

// How far W is from its transpose, found in one pass over its pairs (i, j), i < j: symmetric to the bit,
// near (every |W_ij − W_ji| ≤ kNearSymmetry · max_i |W_ii|, not all zero), or neither (the pass stops
// after the first two columns holding a pair beyond; a non-finite skew is beyond). The diagonal is the
// scale because it is known before the pass, so that an unsymmetric W is told early, as is_symmetric
// tells it at its first unequal pair; of a positive semidefinite W (a Delassus J A⁻¹ Jᵀ) it is max |W|
// itself, |W_ij| ≤ √(W_ii W_jj), and of any other W a stricter scale.
// 16 ε ≈ 3.6e-15: the skews that a Delassus formed in floating point by others carries (the round-off
// of W_ij and W_ji summed in different orders; Siconos' test problems: 1e-17 to 2e-16 of the largest
// entry, docs/contact-problems.md) pass with a margin of 16 or more; skews from a different formation
// (FCLib's, the Rover problems': 1e-7 to 2e-3) are far beyond. The bound decides only which path is
// tried first: a near W's solve is judged on its own rows (PgsSolver's dense path, pgs_solver.cpp).
enum class Symmetry { exact, near, none };
constexpr double kNearSymmetry = 16.0 * 2.220446049250313e-16;
Symmetry symmetry_of(const Eigen::MatrixXd& W);

// A matrix whose column i is W's row i: W itself when it is symmetric to the bit, else Wᵀ, written
// into `transpose` (a solver's work array, its storage reused from solve to solve).
const Eigen::MatrixXd& rows_of(const Eigen::MatrixXd& W, Eigen::MatrixXd& transpose);

using pgs_local::SweepResult;

// sweep<D>: one Gauss–Seidel sweep, dense_sweep.h.

// The full residual, relative (pgs_solver.h); the contacts from settled_from on may be known to
// contribute zero (right after a sweep, SweepResult::settled_from). Flops: about one sweep's.
double relative_residual(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, const Eigen::VectorXd& r,
                         int settled_from);
double relative_residual(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, const Eigen::VectorXd& r);

// The same full residual from W's own rows without reading them: W r formed by columns (contiguous in
// Eigen's storage) into `product` (a work array, m), and each contact's frozen velocity as
// b_c + (W r)_c − W_cc r_c. Exact in arithmetic; in floating point it differs from the sweeps' sum by the
// cancellation's round-off, about ε |W_cc r_c|. All contacts' local solves. Flops: about one sweep's.
double relative_residual_by_columns(const FrictionContactProblem& problem, const Eigen::VectorXd& r,
                                    Eigen::VectorXd& product);

// The active-set iteration from the statuses of r (closed_stick: every closed contact in stick), within
// `budget`; r and residual replaced by a result whose full residual is smaller. True if replaced.
template <int D>
bool active_set_polish(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, Eigen::VectorXd& r,
                       double& residual, bool closed_stick, PolishBudget& budget);

// The polish of the iterate r (the active set, then Newton), within `budget`; r and residual replaced by
// a result whose full residual is smaller. True if replaced.
template <int D>
bool polish(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, Eigen::VectorXd& r, double& residual,
            double tolerance, PolishBudget& budget);

// PgsSolver's dense path on a problem without equality rows (transpose, product: the solver's work
// arrays, Wᵀ and W r).
PgsStatistics solve_contact_rows(const FrictionContactProblem& problem, const PgsParameters& parameters,
                                 Eigen::VectorXd& r, std::vector<ContactStatus>* status, Eigen::MatrixXd& transpose,
                                 Eigen::VectorXd& product);

// The condensed contact rows (condensed.contacts, formed from `problem` by solve_with_equalities) solved
// by the dense path's iteration, whose convergence tests use the full problem's residual
// (recovered_residual): r_c, the contact impulses, on entry the warm start, on exit the solution.
PgsStatistics solve_condensed_rows(const FrictionContactProblem& problem, PgsCondensation& condensed,
                                   const PgsParameters& parameters, Eigen::VectorXd& r_c,
                                   std::vector<ContactStatus>* status, Eigen::MatrixXd& transpose);

// The equality impulses recovered from the contact impulses r_c (r_e = −W_ee⁺ (b_e + W_ec r_c), then
// one step of refinement), the full impulse vector written into r, and the full problem's relative
// residual at r returned. A non-finite r_e (a singular W_ee with inconsistent rows) is set to zero and
// counted in `rejected`.
double recovered_residual(const FrictionContactProblem& problem, PgsCondensation& condensed,
                          const Eigen::VectorXd& r_c, Eigen::VectorXd& r, int& rejected);

// PgsSolver's dense path on a problem with equality rows, condensed out into `condensed`.
PgsStatistics solve_with_equalities(const FrictionContactProblem& problem, const PgsParameters& parameters,
                                    Eigen::VectorXd& r, std::vector<ContactStatus>* status, PgsCondensation& condensed,
                                    Eigen::MatrixXd& transpose);

}  // namespace csim::dense_pgs
