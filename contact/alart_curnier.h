// A semismooth Newton method on the Alart–Curnier equations of the frictional contact problem, used
// to finish what projected Gauss–Seidel leaves unfinished (pgs_solver.h calls it when it stalls).
//
// With u = W r + b and, per contact, a scaling ρ > 0 (rho_scale / the mean of W_cc's diagonal, so
// that ρ u has the units of r), Coulomb's law for isotropic friction is F(r) = 0 with
//   F_n = r_n − max(0, r_n − ρ u_n),
//   F_t = r_t − Proj_{disk of radius μ max(0, r_n − ρ u_n)}(r_t − ρ u_t),
// and F_e = ρ_e u_e on the bilateral rows (Alart & Curnier, CMAME 92, 1991; the "NSN-AC" of
// Acary, Brémond & Huber, 2018). F is piecewise smooth; Newton's step uses an element of its
// generalized Jacobian, damped by a backtracking line search on ½‖F‖².
//
// Where Gauss–Seidel converges linearly at a rate set by the Delassus's condition number (a rigid body
// on two or four points of a stiff elastic one: eigenvalues 1e-5 of the others), Newton converges in
// a few iterations once the contact statuses settle; its cost is one dense LU of the problem's size
// per iteration, bounded by a budget in flops when one is given (PolishBudget, polish_budget.h:
// before each factorization and each line-search trial, the method stops if the work would exceed it).
//
// On a hyperstatic contact set (a body on more points than it has freedoms) J is singular. When the
// partial-pivot LU's step does not solve J s = −F to 1e-8, the proximal step (J + δ I) s = −F is taken
// instead, δ = min(1e-2, max(1e-12, ‖F‖ / scale)) (J dimensionless: ρ scales W_cc's diagonal to one),
// as in sparse_alart_curnier.h: no full pivoting, one more partial-pivot LU.
//
// The scaling matters: with rho_scale = 1, Newton stalled (line search steps of 1e-3) on a box on four
// vertices of a stiff block, whose Delassus has a soft mode across contacts 1e4 below its diagonal;
// with 1e3 it converged in 10 iterations, and both scales solve SSNV503 in 3D in 12 to 16. Callers
// try 1, then 1e3.
//
// Orthotropic friction (μ1 ≠ μ2) is not handled (the projection on an ellipse has no closed form):
// the function then returns false without touching r.
#pragma once

#include "contact/friction_contact_problem.h"

#include <Eigen/Dense>

namespace csim {

struct PolishBudget;  // polish_budget.h

struct NewtonStatistics {
  int iterations = 0;
  double merit = 0.0;  // ‖F(r)‖ at exit, in units of impulse (N·s)
};

// Improves r in place by at most max_iterations Newton steps, stopping when ‖F‖ ≤ tolerance·scale,
// scale = max(‖ρ b‖, ‖r‖), when the line search finds no decrease, or when `budget` (if given) is
// spent; ‖F‖ never increases. Returns false, r untouched, for orthotropic friction or an r of the
// wrong size.
bool alart_curnier_newton(const FrictionContactProblem& problem, Eigen::VectorXd& r, int max_iterations,
                          double tolerance, NewtonStatistics* statistics = nullptr, double rho_scale = 1.0,
                          PolishBudget* budget = nullptr);

}  // namespace csim
