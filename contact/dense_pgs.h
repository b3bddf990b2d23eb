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

// PgsSolver's dense path on a problem without equality rows (transpose: the solver's work array).
PgsStatistics solve_contact_rows(const FrictionContactProblem& problem, const PgsParameters& parameters,
                                 Eigen::VectorXd& r, std::vector<ContactStatus>* status, Eigen::MatrixXd& transpose);

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
