// The semismooth Newton method of alart_curnier.h on a sparse Delassus operator, with a cost bounded by
// a budget and a sound step on a rank-deficient W (the polish of pgs_solver.h's sparse path).
//
// Same equations as alart_curnier.h (Alart & Curnier 1991; the NSN-AC of Acary, Brémond & Huber 2018):
// F(r) = 0 per contact, ρ = rho_scale / the mean of W_cc's diagonal. Row block c of the generalized
// Jacobian is C_c W_c + E_c, a D × D mixing C_c of W's rows of contact c plus a D × D block E_c on the
// diagonal, so J has W's pattern (whole D × D blocks, the diagonal blocks included) and is assembled
// in place of W's values without allocation beyond one array of W's size.
//
// The Newton step J s = −F is solved by UMFPACK's sparse LU (SuiteSparse; the symbolic analysis once
// per call, on W's pattern, whose flop estimate predicts each numeric factorization's cost). On a
// hyperstatic contact set (a body on more contact points than it has freedoms) W, hence J's stick rows,
// is rank deficient: the solution set of F = 0 is an affine family and J is singular there. When the
// plain step fails (a singular factorization, a step that does not solve J s = −F to 1e-8, or one
// the line search cannot use), the step of a proximal (regularized) Newton method is taken instead,
//   (J + δ I) s = −F,   δ = min(1e-2, max(1e-12, √(‖F‖ / scale))),
// (J dimensionless: ρ scales W_cc's diagonal to one), which is defined for J's positive
// semi-definite stick rows, leaves u's range component of F to shrink by δ / (ρλ + δ) per step, and
// tends to Newton's as F → 0: the "proximal point" regularization Siconos offers for NSN-AC. δ plays
// the part of √μ for a Levenberg–Marquardt parameter μ (both turn the step over from Newton's to a
// damped one at J's eigenvalues of that size); μ = ‖F‖ is Fan & Yuan's (2005), which keeps fast local
// convergence on non-isolated solutions as Yamashita & Fukushima's μ = ‖F‖² (2001) does. The latter,
// δ = ‖F‖ / scale, was this method's first choice and stalls on a singular J: F's components along
// J's near-null directions are amplified by 1/δ, 1e6 near a Gauss–Seidel iterate at 1e-6, and the line
// search cuts the step to nothing (Siconos' Capsules-i125-1213, 286 contacts: ‖F‖ unchanged in 30
// steps, four polishes in vain, 803 sweeps and 0.27 s; with √: 400 sweeps, two polishes, 0.10 s;
// Capsules-i122-1617: 20200 sweeps and 101 polishes, 6 s; with √: 1000 sweeps, 5 polishes, 0.47 s).
// No dense factorization, no full pivoting.
//
// Budget: work is counted in flops (a product by W: 2 per stored entry; a factorization: UMFPACK's
// symbolic flop estimate, which its time follows better than the flops it counts; a solve with its
// refinement step: 4 per entry of L and U and a product by J, twice). Before each factorization, and
// before each line-search trial, if the work would exceed budget.available, the method stops
// (budget.exhausted).
//
// Orthotropic friction (μ1 ≠ μ2) is not handled: the function then returns false, r untouched. The
// problem must be stored sparse, without equality rows, and with W_sparse of whole blocks including
// every diagonal block (sparse_pgs.h prepares such a copy when the problem's is not).
#pragma once

#include "contact/alart_curnier.h"
#include "contact/friction_contact_problem.h"
#include "contact/polish_budget.h"

#include <Eigen/Dense>

namespace csim {

// W: the problem's Delassus in the layout above (may be problem.W_sparse itself). Improves r in place by
// at most max_iterations Newton steps, stopping when ‖F‖ ≤ tolerance·max(‖ρ b‖, ‖r‖), when the line
// search finds no decrease or when the budget is spent; ‖F‖ never increases.
bool sparse_alart_curnier_newton(const FrictionContactProblem& problem, const SparseDelassus& W, Eigen::VectorXd& r,
                                 int max_iterations, double tolerance, double rho_scale, PolishBudget& budget,
                                 NewtonStatistics* statistics = nullptr);

}  // namespace csim
