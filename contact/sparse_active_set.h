// The active-set stage of the sparse path's polish (sparse_pgs.h): with each contact's status taken as
// known (open, stick, or slip along a given direction), the law reduces to a square linear system on
// the closed contacts, solved sparsely as a correction of the Gauss–Seidel iterate.
//
// Unknowns and equations per contact (as active_set_polish.cpp's dense active set):
//   open   r_c = 0, no equation;
//   stick  r_c free (its frictionless tangential axes held at 0), u_c = 0 on the same rows;
//   slip   r_c = r_n · slip_ratio (slip_ratio(0) = 1, the tangential part on the cone's boundary),
//          u_n = 0.
// The system A z = f (A: W's rows of the equations times the unknowns' columns, f = −b on those rows)
// is singular on a hyperstatic contact set (a body on more points than it has freedoms): its solutions
// form an affine family, and an arbitrary one (a pivoting LU's basic solution) leaves the cones the
// Gauss–Seidel iterate satisfies. So the stage solves for the correction of the iterate's own z_0 by
// the proximal point method (Rockafellar 1976), which converges on a consistent singular system to the
// solution nearest z_0 in the scaled norm, keeping the iterate's component in A's null space:
//   (Â + ε I) d_k = f̂ − Â ẑ_k,   ẑ_{k+1} = ẑ_k + d_k,
// Â = S A S the system scaled by s_c = 1/√(mean of W_cc's diagonal) on each contact's rows and
// unknowns (its stick diagonal about one), ε = 1e-8. Each step divides A's range component of the
// error by 1 + λ/ε for an eigenvalue λ of Â; one factorization (UMFPACK's sparse LU, as
// sparse_alart_curnier.h) serves every step, stopped when the equations hold to 1e-14 of f or stop
// improving. Â + ε I is positive definite on the stick rows of a symmetric W; slip columns make it
// unsymmetric, and a step that does not decrease ‖Â ẑ − f̂‖ ends the iteration.
//
// Statuses are then corrected from the solution (Hüeber, Stadler & Wohlmuth 2008's primal–dual
// active-set iteration): an open contact that would penetrate closes in stick, a closed one pulling
// (r_n < 0) opens, a stick one outside its cone slips along its impulse, a slip one whose tangential
// velocity does not oppose its impulse sticks.
//
// Work is counted as sparse_alart_curnier.h counts it, in PolishBudget: UMFPACK's symbolic flop estimate
// per factorization, 4 per entry of L and U and a product by A per solve; a factorization that would
// exceed budget.available is refused (budget.exhausted). Orthotropic friction is handled (the cone is
// elliptic); the problem must be stored sparse without equality rows, W of whole blocks with every
// diagonal block (sparse_pgs.h's layout).
#pragma once

#include "contact/coulomb_local.h"
#include "contact/friction_contact_problem.h"
#include "contact/polish_budget.h"

#include <Eigen/Dense>
#include <vector>

namespace csim {

struct ActiveSetStatus {
  ContactStatus status = ContactStatus::open;
  Eigen::Vector3d slip_ratio = Eigen::Vector3d::UnitX();  // slip: r_c = r_n · slip_ratio (first D entries)
};

// The statuses of impulses r (pgs_local.h's status_of); closed_stick puts every closed contact in stick.
std::vector<ActiveSetStatus> statuses_of(const FrictionContactProblem& problem, const Eigen::VectorXd& r,
                                         bool closed_stick);

// Solves the system of `statuses` from the iterate `r` (the correction above) into `candidate`. False
// if there is no closed contact, the budget refused the factorization, or the factorization failed.
bool solve_active_set(const FrictionContactProblem& problem, const SparseDelassus& W,
                      const std::vector<ActiveSetStatus>& statuses, const Eigen::VectorXd& r,
                      Eigen::VectorXd& candidate, PolishBudget& budget);

// Statuses corrected from a solution r of theirs (above); false if none changed.
bool correct_statuses(const FrictionContactProblem& problem, const SparseDelassus& W, const Eigen::VectorXd& r,
                      std::vector<ActiveSetStatus>& statuses);

}  // namespace csim
