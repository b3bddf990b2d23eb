// The active-set polish of PgsSolver's dense path (pgs_solver.h, dense_pgs.h).
//
// Active-set polish: with the statuses of the contacts taken as known, the law reduces to a square
// linear system (stick: u = 0; slip: u_n = 0 with r_t = r_n times a given ratio; open: r = 0; equality
// rows are condensed out before), solved directly. Gauss–Seidel converges slowly when W mixes very
// different scales (a body held by weak springs: rigid-mode entries 1e7 times the elastic ones; a rigid
// body on two points of a stiff elastic one, whose Delassus has an eigenvalue 1e-5 of the others), and
// stalls at a residual of about that ratio times the round-off; the direct solve does not.
// The statuses are then corrected from the solution and the solve repeated (a primal–dual active-set
// iteration, as in Hüeber, Stadler & Wohlmuth, SIAM J. Sci. Comput. 30, 2008): an open contact that
// would penetrate closes in stick, a closed one pulling (r_n < 0) opens, a stick one outside its cone
// slips along its impulse's direction, a slip one whose velocity does not oppose its impulse sticks,
// and a slip one keeps its direction (updating it from the candidate's slip velocity, the direction of
// maximal dissipation, made the iteration wander on SSNV503 in 3D, where all 45 nodes slip at nearly
// the same tiny velocity). The best solution is kept, and only if its full residual is smaller than
// the iterate's.
// Closed rows may be dependent with free terms that disagree, so that no impulses make them all hold:
// in 2D, two vertices of a rigid body on one vertical have the same normal row (0, 1, p_x), and their
// free normal velocities differ by their gap term. A 1 mg shoe under 70 kN (sdnv104-rigid, mass 1e-6)
// has a free velocity of 7e7 m/s, so the step activates its top corners too, 1 m above the ground,
// where u_n(top) = u_n(bottom) + 2000 m/s whatever the impulses. The system of such statuses is then
// solved in the least-squares sense of least norm (not by an LU's arbitrary basic solution, which
// opened a bottom corner and left it penetrating at 2000 m/s, a residual of 1.4e-5 that the
// iteration cycled around), and a closed contact that this solution leaves separating opens: its row
// is redundant and it need not press. The next pass has consistent rows (there: the exact solution,
// residual 7e-17, at the first polish).
//
// Solving a status system A z = b (A: W's closed rows times the statuses' columns, k × k): a partial-pivot
// LU with one step of refinement; where A is singular (a rigid body on more points than it has
// freedoms: its stick rows are dependent) the proximal point iteration
//   z ← z + (A + δ I)⁻¹ (b − A z),   z₀ = 0,   δ = 1e-10 max |A_ij|,
// one partial-pivot LU and a few solves, which contracts the error along an eigenvalue λ of A by
// δ / (λ + δ) a step and leaves z's component along A's null space at zero (a consistent singular
// system ends at about its least-norm solution); an inconsistent one by least squares (above). Each
// factorization is counted in the polish's budget, and refused when the budget has no room for it.
#include "contact/dense_pgs.h"
#include "contact/pgs_local.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace csim::dense_pgs {
namespace {

using pgs_local::Vector;
using pgs_local::cone_ratio;
using pgs_local::status_of;

// Relative mismatch A z − b of a status system above which its closed rows are taken as inconsistent
// (a consistent one, even singular, is solved to about 1e-16 of b after refinement).
constexpr double kInconsistentStatuses = 1e-8;
// Relative mismatch below which a status system is solved (the plain LU's test).
constexpr double kSolved = 1e-10;
// The proximal iteration's δ relative to A's largest entry, and its steps at most.
constexpr double kProximal = 1e-10;
constexpr int kProximalSteps = 10;

template <int D>
struct PolishStatus {
  ContactStatus status = ContactStatus::open;
  Vector<D> slip_ratio = Vector<D>::Zero();  // slip: r = r_n · slip_ratio, slip_ratio(0) = 1
};

// A status system's unknowns (the columns of S): an unknown's entries start at row `first` and span at
// most D rows (a slip contact's normal with its tangential ratio), the others are a single 1; and the
// rows of u it sets to zero.
template <int D>
struct StatusSystem {
  struct Unknown {
    Eigen::Index first;
    Vector<D> column;
  };
  std::vector<Eigen::Index> equations;
  std::vector<Unknown> unknowns;
  Eigen::MatrixXd A;  // (W S) restricted to the equations' rows
  Eigen::VectorXd b;  // −b restricted to them
};

template <int D>
void form_system(const FrictionContactProblem& problem, const std::vector<PolishStatus<D>>& statuses,
                 StatusSystem<D>& system) {
  const Eigen::Index m = problem.size();
  const Vector<D> unit = Vector<D>::Unit(0);
  for (int c = 0; c < problem.contacts; ++c) {
    const Eigen::Index row = static_cast<Eigen::Index>(D) * c;
    const PolishStatus<D>& status = statuses[c];
    if (status.status == ContactStatus::open) continue;
    system.equations.push_back(row);
    if (status.status == ContactStatus::slip) {
      system.unknowns.push_back({row, status.slip_ratio});
      continue;
    }
    system.unknowns.push_back({row, unit});
    for (int k = 1; k < D; ++k) {
      if (!(problem.mu[c](k - 1) > 0.0)) continue;
      system.unknowns.push_back({row + k, unit});
      system.equations.push_back(row + k);
    }
  }
  const Eigen::Index k = static_cast<Eigen::Index>(system.unknowns.size());
  system.A.setZero(k, k);
  system.b.resize(k);
  for (Eigen::Index j = 0; j < k; ++j) {
    const auto& u = system.unknowns[j];
    for (Eigen::Index l = 0; l < std::min<Eigen::Index>(D, m - u.first); ++l) {
      if (u.column(l) == 0.0) continue;
      for (Eigen::Index i = 0; i < k; ++i) system.A(i, j) += problem.W(system.equations[i], u.first + l) * u.column(l);
    }
  }
  for (Eigen::Index i = 0; i < k; ++i) system.b(i) = -problem.b(system.equations[i]);
}

enum class Solved { yes, no, refused };

// A z = b by the partial-pivot LU and its refinement step, then (A singular) by the proximal iteration,
// then (inconsistent rows: consistent = false) by least squares of least norm. `reserve`: the flops
// the pass still needs after this solve.
Solved solve_system(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, double reserve, PolishBudget& budget,
                    Eigen::VectorXd& z, bool& consistent) {
  consistent = true;
  const double k = static_cast<double>(A.rows()), lu_flops = 2.0 / 3.0 * k * k * k, step_flops = 4.0 * k * k;
  const double norm_b = b.norm();
  if (!budget.afford(lu_flops + 2.0 * step_flops, reserve)) return Solved::refused;
  ++budget.factorizations;
  const Eigen::PartialPivLU<Eigen::MatrixXd> plain(A);
  z = plain.solve(b);
  z += plain.solve(b - A * z);  // one step of refinement (W's condition number reaches 1e8)
  if (z.allFinite() && (A * z - b).norm() <= kSolved * norm_b) return Solved::yes;
  if (!budget.afford(lu_flops + kProximalSteps * step_flops, reserve)) return Solved::refused;
  ++budget.factorizations;
  ++budget.regularized_steps;
  Eigen::MatrixXd shifted = A;
  shifted.diagonal().array() += kProximal * A.cwiseAbs().maxCoeff();
  const Eigen::PartialPivLU<Eigen::MatrixXd> proximal(shifted);
  z.setZero(A.rows());
  Eigen::VectorXd mismatch = b;
  for (int step = 0; step < kProximalSteps && mismatch.norm() > kSolved * norm_b; ++step) {
    z += proximal.solve(mismatch);
    mismatch = b - A * z;
    if (!mismatch.allFinite()) break;
  }
  if (mismatch.allFinite() && mismatch.norm() <= kInconsistentStatuses * norm_b) return Solved::yes;
  // The closed rows are dependent and their free terms disagree (the statuses cannot all hold): the
  // least-squares solution of least norm, which leaves the redundant contact that need not press
  // separating, so that the correction opens it.
  consistent = false;
  if (!budget.afford(3.0 * k * k * k, reserve)) return Solved::refused;
  ++budget.factorizations;
  z = A.completeOrthogonalDecomposition().solve(b);
  return z.allFinite() ? Solved::yes : Solved::no;
}

// The impulses of the given statuses into `candidate`; false if there are none to solve for, the
// system has no finite solution, or the budget refuses it.
template <int D>
bool solve_statuses(const FrictionContactProblem& problem, const std::vector<PolishStatus<D>>& statuses,
                    PolishBudget& budget, Eigen::VectorXd& candidate, bool& consistent) {
  StatusSystem<D> system;
  form_system<D>(problem, statuses, system);
  const Eigen::Index k = static_cast<Eigen::Index>(system.unknowns.size());
  if (k == 0) return false;
  const double m = static_cast<double>(problem.size());
  // Forming A (k² entries, a few flops each), then the pass's residual and status correction (two
  // products by W).
  if (!budget.afford(2.0 * D * static_cast<double>(k * k), 4.0 * m * m)) return false;
  Eigen::VectorXd z;
  if (solve_system(system.A, system.b, 4.0 * m * m, budget, z, consistent) != Solved::yes) return false;
  candidate.setZero(problem.size());
  for (Eigen::Index j = 0; j < k; ++j) {
    const auto& u = system.unknowns[j];
    const Eigen::Index span = std::min<Eigen::Index>(D, problem.size() - u.first);
    candidate.segment(u.first, span) += z(j) * u.column.head(span);
  }
  return true;
}

// Statuses corrected from a solution r of the previous statuses (see above); false if none changed.
template <int D>
bool correct_statuses(const FrictionContactProblem& problem, const Eigen::VectorXd& r,
                      std::vector<PolishStatus<D>>& statuses, bool consistent) {
  const Eigen::VectorXd u = problem.W * r + problem.b;
  // A closed contact separates only where the solve could not hold every closed row (an inconsistent
  // system): there u_n > 0 beyond round-off says that its row is redundant and it need not press.
  const double separating = consistent ? std::numeric_limits<double>::infinity()
                                       : kInconsistentStatuses * problem.b.norm();
  bool changed = false;
  for (int c = 0; c < problem.contacts; ++c) {
    const Eigen::Index row = static_cast<Eigen::Index>(D) * c;
    const Vector<D> rc = r.template segment<D>(row), uc = u.template segment<D>(row);
    PolishStatus<D>& s = statuses[c];
    const PolishStatus<D> before = s;
    if (s.status == ContactStatus::open) {
      if (uc(0) < 0.0) s.status = ContactStatus::stick;
    } else if (!(rc(0) > 0.0) || uc(0) > separating) {
      s.status = ContactStatus::open;
    } else if (s.status == ContactStatus::stick) {
      if (cone_ratio<D>(rc, problem.mu[c]) > 1.0) {
        s.status = ContactStatus::slip;
        s.slip_ratio = rc / (rc(0) * cone_ratio<D>(rc, problem.mu[c]));
        s.slip_ratio(0) = 1.0;
      }
    } else if (rc.template tail<D - 1>().dot(uc.template tail<D - 1>()) > 0.0) {
      s.status = ContactStatus::stick;  // a slip whose velocity does not oppose its impulse
    }
    changed = changed || s.status != before.status || s.slip_ratio != before.slip_ratio;
  }
  return changed;
}

// Passes of the active-set iteration per polish; each costs one dense solve of the closed rows.
constexpr int kActiveSetPasses = 8;

}  // namespace

template <int D>
bool active_set_polish(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, Eigen::VectorXd& r,
                       double& residual, bool closed_stick, PolishBudget& budget) {
  std::vector<PolishStatus<D>> statuses(problem.contacts);
  for (int c = 0; c < problem.contacts; ++c) {
    const Vector<D> rc = r.template segment<D>(static_cast<Eigen::Index>(D) * c);
    PolishStatus<D>& s = statuses[c];
    s.status = status_of<D>(rc, problem.mu[c]);
    if (s.status == ContactStatus::slip) s.slip_ratio = rc / rc(0);
    if (closed_stick && s.status != ContactStatus::open) s.status = ContactStatus::stick;
  }
  const double m = static_cast<double>(problem.size());
  bool improved = false;
  Eigen::VectorXd candidate;
  for (int pass = 0; pass < kActiveSetPasses; ++pass) {
    bool consistent = true;
    if (!solve_statuses<D>(problem, statuses, budget, candidate, consistent)) break;
    const double candidate_residual = relative_residual(problem, W_rows, candidate);
    budget.spent += 4.0 * m * m;  // the residual and the correction's product by W
    if (candidate_residual < residual) {
      r = candidate;
      residual = candidate_residual;
      improved = true;
    }
    if (!correct_statuses<D>(problem, candidate, statuses, consistent)) break;
  }
  return improved;
}

template bool active_set_polish<2>(const FrictionContactProblem&, const Eigen::MatrixXd&, Eigen::VectorXd&, double&,
                                   bool, PolishBudget&);
template bool active_set_polish<3>(const FrictionContactProblem&, const Eigen::MatrixXd&, Eigen::VectorXd&, double&,
                                   bool, PolishBudget&);

}  // namespace csim::dense_pgs
