#include "contact/pgs_solver.h"

#include "contact/alart_curnier.h"
#include "contact/pgs_local.h"
#include "contact/sparse_pgs.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

// Implementation notes.
// - The coupling of contact c with the others is W's rows c (u = W r + b), read as the contiguous
//   columns of a matrix `W_rows` whose column i is W's row i (Eigen stores by column): W itself when W
//   is symmetric to the bit (every Delassus the steppers form), else Wᵀ, copied once per solve
//   (rows_of). A row read down a column-major W strides by its size, several times slower.
// - Per-contact work is templated on the contact dimension and uses fixed-size Eigen objects: a solve
//   without equality rows does not allocate at all; with equalities the condensed problem's arrays are
//   the solver's (PgsCondensation), reused from solve to solve.

namespace csim {
namespace {

using pgs_local::Matrix;
using pgs_local::Vector;
using pgs_local::cone_ratio;
using pgs_local::keep_in_cone;
using pgs_local::solve_local;
using pgs_local::status_of;
using pgs_local::velocity_scale;

// Sweeps between two attempts at the active-set polish (see polish()).
constexpr int kPolishInterval = 200;
// ... and once early, after 20 sweeps: when a few sweeps have sorted out the statuses, the direct
// solve finishes a problem that Gauss–Seidel would take hundreds of sweeps over (an ill-conditioned
// Delassus). A sweep costs about m² for m rows and the polish's LU m³/3 (sdnv104-quad4 with 81
// contacts, where every solve needs the polish: 7.6 ms per step).
constexpr int kFirstPolish = 20;

void check_problem(const FrictionContactProblem& problem) {
  if (const std::string problem_with_it = inconsistency(problem); !problem_with_it.empty())
    throw std::invalid_argument("PgsSolver: " + problem_with_it);
}

// Free velocity of the contact whose rows start at `first`, with every other impulse frozen at r
// (m/s): b_c + Σ_{d≠c} W_cd r_d. The own block is skipped rather than subtracted, so that with a
// single contact this is b_c exactly and the local solve is the global one to the last bit.
// The contact's D rows of W (W_rows' columns, contiguous) are summed side by side, four entries
// a pass in two packets of two, whose four partial sums are added at the end: Eigen's general product
// costs more in set-up than a dozen rows' arithmetic, and with a single packet a column each addition
// waits on the last, which made 2D sweeps slower than Eigen's (bench/bench_pgs).
template <int D>
Vector<D> frozen_free_velocity(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows,
                               const Eigen::VectorXd& r, Eigen::Index first) {
  Vector<D> b_c = problem.b.template segment<D>(first);
  const Eigen::Index n = r.size();
  if (n == D) return b_c;
  const double* column[D];
  for (int k = 0; k < D; ++k) column[k] = W_rows.col(first + k).data();
  const double* x = r.data();
  using Pair = Eigen::Map<const Eigen::Vector2d>;
  Eigen::Vector2d pairs[2][D];
  double last[D];
  for (int k = 0; k < D; ++k) {
    pairs[0][k].setZero();
    pairs[1][k].setZero();
    last[k] = 0.0;
  }
  const auto add_rows = [&](Eigen::Index j, Eigen::Index end) {
    for (; j + 3 < end; j += 4) {
      const Pair x_j(x + j), x_next(x + j + 2);
      for (int k = 0; k < D; ++k) {
        pairs[0][k] += Pair(column[k] + j).cwiseProduct(x_j);
        pairs[1][k] += Pair(column[k] + j + 2).cwiseProduct(x_next);
      }
    }
    if (j + 1 < end) {
      const Pair x_j(x + j);
      for (int k = 0; k < D; ++k) pairs[0][k] += Pair(column[k] + j).cwiseProduct(x_j);
      j += 2;
    }
    if (j < end)
      for (int k = 0; k < D; ++k) last[k] += column[k][j] * x[j];
  };
  add_rows(0, first);
  add_rows(first + D, n);
  for (int k = 0; k < D; ++k) {
    const Eigen::Vector2d sum = pairs[0][k] + pairs[1][k];
    b_c(k) += (sum(0) + sum(1)) + last[k];
  }
  return b_c;
}

// ‖(W r)_c‖², (m/s)², of the contact whose rows start at `first`, from its frozen velocity (above) and
// its impulse r_c: (frozen − b_c) + W_cc r_c.
template <int D>
double product_squared(const FrictionContactProblem& problem, Eigen::Index first, const Vector<D>& frozen,
                       const Matrix<D>& W_cc, const Vector<D>& r_c) {
  return (frozen - problem.b.template segment<D>(first) + W_cc * r_c).squaredNorm();
}

// True if W equals its transpose to the bit.
bool is_symmetric(const Eigen::MatrixXd& W) {
  const Eigen::Index m = W.rows();
  for (Eigen::Index j = 0; j < m; ++j)
    for (Eigen::Index i = j + 1; i < m; ++i)
      if (W(i, j) != W(j, i)) return false;
  return true;
}

// A matrix whose column i is W's row i: W itself when it is symmetric to the bit, else Wᵀ, written
// into `transpose` (a solver's work array, its storage reused from solve to solve).
const Eigen::MatrixXd& rows_of(const Eigen::MatrixXd& W, Eigen::MatrixXd& transpose) {
  if (is_symmetric(W)) return W;
  transpose.noalias() = W.transpose();
  return transpose;
}

struct SweepResult {
  double increment_squared = 0.0;  // Σ (W_ii Δr_i)², (m/s)²
  double Wr_squared = 0.0;         // ≈ ‖W r‖², from the velocities seen during the sweep, (m/s)²
  // The contacts from this one on have a zero term in the full residual at the sweep's result, known
  // without solving them again: after the last contact whose impulse moved, no impulse changed, so
  // each later contact (and that one, if its impulse is its local solution, omega = 1) sees at the end
  // the frozen velocity it was solved with, and its local solution is its impulse bit for bit. 0 when
  // every local solve returned the impulse it started from; a rejected contact is never settled.
  int settled_from = 0;
};

template <int D>
SweepResult sweep(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows,
                  const PgsParameters& parameters, Eigen::VectorXd& r, int& rejected) {
  SweepResult result;
  for (int c = 0; c < problem.contacts; ++c) {
    const Eigen::Index first = static_cast<Eigen::Index>(D) * c;
    const Vector<D> b_c = frozen_free_velocity<D>(problem, W_rows, r, first);
    const Matrix<D> W_cc = problem.W.template block<D, D>(first, first);
    const Eigen::Vector2d& mu = problem.mu[c];
    Vector<D> r_local;
    solve_local<D>(W_cc, b_c, mu, r_local);
    const Vector<D> r_old = r.template segment<D>(first);
    if (!r_local.allFinite()) {
      ++rejected;
      result.settled_from = c + 1;
      result.Wr_squared += product_squared<D>(problem, first, b_c, W_cc, r_old);
      continue;
    }
    Vector<D> r_new = r_local;
    if (parameters.omega != 1.0) {
      r_new = r_old + parameters.omega * (r_local - r_old);
      if (parameters.omega > 1.0) keep_in_cone<D>(r_new, mu);
    }
    if (r_new != r_old || r_local != r_new) result.settled_from = r_local == r_new ? c : c + 1;
    result.increment_squared += W_cc.diagonal().cwiseProduct(r_new - r_old).squaredNorm();
    result.Wr_squared += product_squared<D>(problem, first, b_c, W_cc, r_new);
    r.template segment<D>(first) = r_new;
  }

  return result;
}

// The sums a relative residual is made of, (m/s)².
struct ResidualSums {
  double law = 0.0;      // the law's terms: Σ_c ‖W_cc (r_c − local_c(r))‖² + ‖u_e‖²
  double product = 0.0;  // ‖W r‖², the scale's
};

// The equality rows' terms: u_e = (W r)_e + b_e, (W r)_j = W_rows.col(j)·r.
void add_equality_sums(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, const Eigen::VectorXd& r,
                       ResidualSums& sums) {
  const Eigen::Index first = static_cast<Eigen::Index>(problem.dimension) * problem.contacts;
  for (Eigen::Index j = first; j < problem.size(); ++j) {
    const double Wr_j = W_rows.col(j).dot(r);
    const double u_j = Wr_j + problem.b(j);
    sums.law += u_j * u_j;
    sums.product += Wr_j * Wr_j;
  }
}

// The contacts' terms; the law's is infinite if a local solution is not finite. The law's terms of the
// contacts from `settled_from` on are known to be zero (SweepResult) and not computed: adding them
// would add +0 to the sum, which leaves it the same to the bit. (W r)_c comes from the frozen velocity
// (product_squared), formed for every contact so that a skipped term leaves the scale the same to the
// bit too: the subtraction's round-off, a fraction 1e-16 of ‖b‖, is below what a scale of
// max(‖b‖, ‖W r‖) can see.
template <int D>
void add_contact_sums(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, const Eigen::VectorXd& r,
                      int settled_from, ResidualSums& sums) {
  for (int c = 0; c < problem.contacts; ++c) {
    const Eigen::Index first = static_cast<Eigen::Index>(D) * c;
    const Vector<D> b_c = frozen_free_velocity<D>(problem, W_rows, r, first);
    const Matrix<D> W_cc = problem.W.template block<D, D>(first, first);
    const Vector<D> r_c = r.template segment<D>(first);
    sums.product += product_squared<D>(problem, first, b_c, W_cc, r_c);
    if (c >= settled_from) continue;
    Vector<D> r_local;
    solve_local<D>(W_cc, b_c, problem.mu[c], r_local);
    if (!r_local.allFinite()) {
      sums.law = std::numeric_limits<double>::infinity();
      return;
    }
    sums.law += (W_cc * (r_c - r_local)).squaredNorm();
  }
}

// The full residual, relative; the contacts from settled_from on may be known to contribute zero
// (right after a sweep, SweepResult::settled_from).
double relative_residual(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, const Eigen::VectorXd& r,
                         int settled_from) {
  ResidualSums sums;
  add_equality_sums(problem, W_rows, r, sums);
  if (problem.dimension == 2) add_contact_sums<2>(problem, W_rows, r, settled_from, sums);
  else add_contact_sums<3>(problem, W_rows, r, settled_from, sums);
  const double residual = std::sqrt(sums.law) / velocity_scale(problem.b.norm(), std::sqrt(sums.product));
  return std::isnan(residual) ? std::numeric_limits<double>::infinity() : residual;
}

double relative_residual(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, const Eigen::VectorXd& r) {
  return relative_residual(problem, W_rows, r, problem.contacts);
}

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
// solved in the least-squares sense of least norm (not by the LU's arbitrary basic solution, which
// opened a bottom corner and left it penetrating at 2000 m/s, a residual of 1.4e-5 that the
// iteration cycled around), and a closed contact that this solution leaves separating opens: its row
// is redundant and it need not press. The next pass has consistent rows (there: the exact solution,
// residual 7e-17, at the first polish).
// Relative mismatch A z − b of a status system above which its closed rows are taken as inconsistent
// (a consistent one, even singular, is solved to about 1e-16 of b after the refinement step).
constexpr double kInconsistentStatuses = 1e-8;

template <int D>
struct PolishStatus {
  ContactStatus status = ContactStatus::open;
  Vector<D> slip_ratio = Vector<D>::Zero();  // slip: r = r_n · slip_ratio, slip_ratio(0) = 1
};

template <int D>
bool solve_statuses(const FrictionContactProblem& problem, const std::vector<PolishStatus<D>>& statuses,
                    Eigen::VectorXd& candidate, bool& consistent) {
  consistent = true;
  const Eigen::Index m = problem.size();
  // An unknown is a column of S: its entries start at row `first` and span at most D rows (a slip
  // contact's normal with its tangential ratio), the others are a single 1.
  struct Unknown {
    Eigen::Index first;
    Vector<D> column;
  };
  const Vector<D> unit = Vector<D>::Unit(0);
  std::vector<Eigen::Index> equations;  // rows of u set to zero
  std::vector<Unknown> unknowns;
  for (int c = 0; c < problem.contacts; ++c) {
    const Eigen::Index row = static_cast<Eigen::Index>(D) * c;
    const PolishStatus<D>& status = statuses[c];
    if (status.status == ContactStatus::open) continue;
    equations.push_back(row);
    if (status.status == ContactStatus::slip) {
      unknowns.push_back({row, status.slip_ratio});
      continue;
    }
    unknowns.push_back({row, unit});
    for (int k = 1; k < D; ++k) {
      if (!(problem.mu[c](k - 1) > 0.0)) continue;
      unknowns.push_back({row + k, unit});
      equations.push_back(row + k);
    }
  }
  const Eigen::Index k = static_cast<Eigen::Index>(unknowns.size());
  if (k == 0) return false;
  // A = (W S) restricted to the equations' rows.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(k, k);
  Eigen::VectorXd b(k);
  for (Eigen::Index j = 0; j < k; ++j) {
    const Unknown& u = unknowns[j];
    for (Eigen::Index l = 0; l < std::min<Eigen::Index>(D, m - u.first); ++l) {
      if (u.column(l) == 0.0) continue;
      for (Eigen::Index i = 0; i < k; ++i) A(i, j) += problem.W(equations[i], u.first + l) * u.column(l);
    }
  }
  for (Eigen::Index i = 0; i < k; ++i) b(i) = -problem.b(equations[i]);
  // Partial pivoting (blocked, about ten times faster than full pivoting at a hundred rows) unless
  // the system is singular, as for a rigid body on more points than it has freedoms.
  Eigen::VectorXd z;
  const Eigen::PartialPivLU<Eigen::MatrixXd> fast(A);
  z = fast.solve(b);
  z += fast.solve(b - A * z);  // one step of refinement (W's condition number reaches 1e8)
  if (!z.allFinite() || (A * z - b).norm() > 1e-10 * b.norm()) {
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
    z = lu.solve(b);
    z += lu.solve(b - A * z);
    // Still not solved: the closed rows are dependent and their free terms disagree (the statuses
    // cannot all hold). The least-squares solution of least norm instead of the LU's arbitrary one:
    // it leaves the redundant contact that need not press separating, which the correction opens.
    if (!z.allFinite() || (A * z - b).norm() > kInconsistentStatuses * b.norm()) {
      consistent = false;
      z = A.completeOrthogonalDecomposition().solve(b);
    }
  }
  if (!z.allFinite()) return false;
  candidate.setZero(m);
  for (Eigen::Index j = 0; j < k; ++j) {
    const Unknown& u = unknowns[j];
    const Eigen::Index span = std::min<Eigen::Index>(D, m - u.first);
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

template <int D>
bool active_set_polish(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, Eigen::VectorXd& r,
                       double& residual, bool closed_stick) {
  std::vector<PolishStatus<D>> statuses(problem.contacts);
  for (int c = 0; c < problem.contacts; ++c) {
    const Vector<D> rc = r.template segment<D>(static_cast<Eigen::Index>(D) * c);
    PolishStatus<D>& s = statuses[c];
    s.status = status_of<D>(rc, problem.mu[c]);
    if (s.status == ContactStatus::slip) s.slip_ratio = rc / rc(0);
    if (closed_stick && s.status != ContactStatus::open) s.status = ContactStatus::stick;
  }
  bool improved = false;
  Eigen::VectorXd candidate;
  for (int pass = 0; pass < kActiveSetPasses; ++pass) {
    bool consistent = true;
    if (!solve_statuses<D>(problem, statuses, candidate, consistent)) break;
    const double candidate_residual = relative_residual(problem, W_rows, candidate);
    if (candidate_residual < residual) {
      r = candidate;
      residual = candidate_residual;
      improved = true;
    }
    if (!correct_statuses<D>(problem, candidate, statuses, consistent)) break;
  }
  return improved;
}

// Newton steps per polish; each costs a dense LU of the problem's size.
constexpr int kNewtonIterations = 30;

// Alart–Curnier Newton from `start` at each ρ scale in turn, until the residual reaches the tolerance;
// a result replaces r only if its full residual is smaller. True if r was replaced.
bool newton_polish(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, const Eigen::VectorXd& start,
                   Eigen::VectorXd& r, double& residual, double tolerance) {
  bool improved = false;
  for (const double rho_scale : {1.0, 1e3}) {
    if (residual <= tolerance) break;
    Eigen::VectorXd candidate = start;
    if (!alart_curnier_newton(problem, candidate, kNewtonIterations, 1e-3 * tolerance, nullptr, rho_scale)) break;
    const double candidate_residual = relative_residual(problem, W_rows, candidate);
    if (candidate_residual < residual) {
      r = candidate;
      residual = candidate_residual;
      improved = true;
    }
  }
  return improved;
}

// The polish: the active-set iteration from the iterate's statuses, then from "every closed contact in
// stick" (the usual state of a pressed interface, which a slowly converging iterate misclassifies at
// the cone's edge), then the semismooth Newton method (alart_curnier.h), which also finds slip
// directions in 3D. Each result is kept only if its full residual is smaller.
//
// Newton starts from Gauss–Seidel's own iterate, not from an active-set result. A contact whose t2 row
// of W is zero (a node held across the ground's sliding direction: the plane-strain ring under a
// cornering ground, with a lateral slip of 1e-7 of the step's) can slip only along t2's fixed velocity;
// the active set may put it in stick with r_t2 = 0, a state whose residual looks smaller (the
// residual weighs r_t2 by W_cc, here zero) but from which Newton cannot move (its stick Jacobian row
// is zero) and the line search stops at once. From the Gauss–Seidel iterate, where the local solves
// have put that contact in slip, Newton converged in 2 to 10 steps on every such problem met
// (rolling-ring-3d on 34 × 5), where the former order left relative residuals of 3e-7 to 2e-6.
template <int D>
bool polish(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, Eigen::VectorXd& r, double& residual,
            double tolerance) {
  const Eigen::VectorXd iterate = r;
  bool moved_by_active_set = active_set_polish<D>(problem, W_rows, r, residual, false);
  if (residual > tolerance)
    moved_by_active_set = active_set_polish<D>(problem, W_rows, r, residual, true) || moved_by_active_set;
  // Newton from the iterate, then from the active set's result if it differs (the former start, kept
  // second so that no problem the former order solved is lost).
  const Eigen::VectorXd active_set_result = r;
  bool improved = newton_polish(problem, W_rows, iterate, r, residual, tolerance) || moved_by_active_set;
  if (moved_by_active_set)
    improved = newton_polish(problem, W_rows, active_set_result, r, residual, tolerance) || improved;
  return improved;
}

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
    ++statistics.polishes;
    polished_after = statistics.iterations;
    if (polish<D>(problem, W_rows, r, statistics.residual, parameters.tolerance)) statistics.polished = true;
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

// Relative size, against the full problem's entries, below which a condensed entry is round-off: the
// cancellation leaves about eps · cond(W_ee) of them (cond(W_ee) ≈ 2e4 on a ring tied to a light hub).
constexpr double kCondensationRoundOff = 1e-11;

// condense()'s part that depends on W alone: W_ee's factorization, X and the condensed W.
void condense_operator(const FrictionContactProblem& problem, PgsCondensation& condensed) {
  const Eigen::Index m_c = static_cast<Eigen::Index>(problem.dimension) * problem.contacts;
  const Eigen::Index m_e = problem.equalities;
  condensed.symmetric = is_symmetric(problem.W);
  if (condensed.symmetric) {
    condensed.W_ee.compute(problem.W.bottomRightCorner(m_e, m_e));
    condensed.X = condensed.W_ee.solve(problem.W.bottomLeftCorner(m_e, m_c));
    condensed.W_transpose.resize(0, 0);
  } else {
    // An unsymmetric W (a library user's): W_ee by a complete orthogonal decomposition, whose solve is
    // the minimum-norm least-squares one, so that redundant consistent rows stay allowed.
    condensed.W_ee_general.compute(problem.W.bottomRightCorner(m_e, m_e));
    condensed.X = condensed.W_ee_general.solve(problem.W.bottomLeftCorner(m_e, m_c));
    condensed.W_transpose = problem.W.transpose();
  }
  FrictionContactProblem& contacts = condensed.contacts;
  contacts.W = problem.W.topLeftCorner(m_c, m_c);
  contacts.W.noalias() -= problem.W.topRightCorner(m_c, m_e) * condensed.X;
  // Of a symmetric W, symmetric up to round-off; made exactly so, so that the sweeps read its rows from
  // its columns (rows_of) and give the same impulses as before. An unsymmetric W's is left as it is.
  if (condensed.symmetric)
    for (Eigen::Index j = 0; j < m_c; ++j)
      for (Eigen::Index i = 0; i < j; ++i) contacts.W(i, j) = contacts.W(j, i) = 0.5 * (contacts.W(i, j) + contacts.W(j, i));
  // The difference cancels the entries the ties make rigid: a node held across the ground by the
  // body's constraints has a zero column once condensed, which comes out as round-off of the full
  // entries (3e-16 of them on the tied 3D ring). Such a column must be exactly zero: on round-off the
  // polish's direct solves put unbounded impulses along it that the condensed residual (which weighs
  // them by that column) does not see, and the full problem does (1e14 on that ring).
  condensed.full_scale = problem.W.diagonal().head(m_c).cwiseAbs().cwiseSqrt();
  const Eigen::VectorXd& full_scale = condensed.full_scale;
  for (Eigen::Index j = 0; j < m_c; ++j)
    for (Eigen::Index i = 0; i < m_c; ++i)
      if (std::abs(contacts.W(i, j)) <= kCondensationRoundOff * full_scale(i) * full_scale(j))
        contacts.W(i, j) = 0.0;
  condensed.W = problem.W;
  condensed.dimension = problem.dimension;
  condensed.contact_count = problem.contacts;
  condensed.equalities = problem.equalities;
}

// The bilateral rows condensed out (see the header): for given contact impulses r_c the equality rows
// u_e = W_ec r_c + W_ee r_e + b_e = 0 give r_e = −W_ee⁺ (b_e + W_ec r_c), so the contacts see the Schur
// complement W_cc − W_ce W_ee⁺ W_ec and the free velocity b_c − W_ce W_ee⁺ b_e. (W_ee⁺: the LDLT's
// solve, which skips zero pivots, so redundant but consistent rows are allowed.)
// The contact rows' problem with the equalities condensed out, into `condensed` (its arrays reused).
void condense(const FrictionContactProblem& problem, PgsCondensation& condensed) {
  const Eigen::Index m_c = static_cast<Eigen::Index>(problem.dimension) * problem.contacts;
  const Eigen::Index m_e = problem.equalities;
  FrictionContactProblem& contacts = condensed.contacts;
  contacts.dimension = problem.dimension;
  contacts.contacts = problem.contacts;
  contacts.equalities = 0;
  contacts.mu = problem.mu;
  const bool formed = condensed.dimension == problem.dimension && condensed.contact_count == problem.contacts &&
                      condensed.equalities == problem.equalities && condensed.W.rows() == problem.W.rows() &&
                      condensed.W.cols() == problem.W.cols() && condensed.W == problem.W;
  if (!formed) condense_operator(problem, condensed);
  condensed.x_b = problem.b.tail(m_e);
  condensed.solve_equalities(condensed.x_b);
  // Each product into its array, then combined: the same operations as on temporaries, to the bit.
  contacts.b.noalias() = problem.W.topRightCorner(m_c, m_e) * condensed.x_b;
  contacts.b = problem.b.head(m_c) - contacts.b;
}

// Gauss–Seidel on the condensed contact rows, then r_e from r_c, with one step of refinement on the
// equality rows (W_ee's condition number is 2e4 on the 3D ring tied to a light hub). Converged is
// decided on the full problem's residual.
PgsStatistics solve_with_equalities(const FrictionContactProblem& problem, const PgsParameters& parameters,
                                    Eigen::VectorXd& r, std::vector<ContactStatus>* status,
                                    PgsCondensation& condensed, Eigen::MatrixXd& transpose) {
  const Eigen::Index m_c = static_cast<Eigen::Index>(problem.dimension) * problem.contacts;
  const Eigen::Index m_e = problem.equalities;
  condense(problem, condensed);
  Eigen::VectorXd& r_c = condensed.r_c;
  Eigen::VectorXd& r_e = condensed.r_e;
  Eigen::VectorXd& u_e = condensed.u_e;
  r_c = r.head(m_c);
  PgsStatistics statistics = solve_contact_rows(condensed.contacts, parameters, r_c, status, transpose);
  Eigen::VectorXd& product = condensed.product;
  r_e.noalias() = condensed.X * r_c;
  r_e = -(condensed.x_b + r_e);
  u_e.noalias() = problem.W.bottomLeftCorner(m_e, m_c) * r_c;
  product.noalias() = problem.W.bottomRightCorner(m_e, m_e) * r_e;
  u_e = u_e + product + problem.b.tail(m_e);
  condensed.solve_equalities(u_e);
  r_e -= u_e;
  // r_c is finite (the sweeps reject non-finite local results, the polish keeps only a smaller finite
  // residual); r_e is not when W_ee is singular and its rows inconsistent.
  if (!r_e.allFinite()) {
    ++statistics.rejected_local_solutions;
    r_e.setZero();
  }
  r.head(m_c) = r_c;
  r.tail(m_e) = r_e;
  statistics.residual = relative_residual(problem, condensed.symmetric ? problem.W : condensed.W_transpose, r);
  statistics.converged = statistics.residual <= parameters.tolerance;
  return statistics;
}

}  // namespace

void PgsCondensation::solve_equalities(Eigen::VectorXd& x) const {
  if (!symmetric) {
    x = W_ee_general.solve(x);
    return;
  }
  if (x.size() != 1) {
    W_ee.solveInPlace(x);
    return;
  }
  // Eigen's LDLT of a 1 × 1 matrix: no transposition, L = 1, D = W_ee; its solve divides by D when
  // |D| exceeds the smallest normal double, and gives 0 otherwise (the pseudo-inverse).
  const double D = W_ee.vectorD()(0);
  x(0) = std::abs(D) > std::numeric_limits<double>::min() ? x(0) / D : 0.0;
}

PgsStatistics PgsSolver::solve(const FrictionContactProblem& problem, Eigen::VectorXd& r,
                               std::vector<ContactStatus>* status) const {
  check_problem(problem);
  // A warm start of the wrong size, or one carrying NaN/inf from an earlier failure, is worthless.
  if (r.size() != problem.size() || !r.allFinite()) r = Eigen::VectorXd::Zero(problem.size());
  if (problem.storage == DelassusStorage::sparse) return solve_sparse(problem, parameters_, r, status, scratch_.completed);
  if (problem.equalities > 0)
    return solve_with_equalities(problem, parameters_, r, status, scratch_.condensation, scratch_.transpose);
  return solve_contact_rows(problem, parameters_, r, status, scratch_.transpose);
}

double PgsSolver::residual(const FrictionContactProblem& problem, const Eigen::VectorXd& r) {
  check_problem(problem);
  if (r.size() != problem.size())
    throw std::invalid_argument("PgsSolver::residual: r has the wrong size");
  if (problem.size() == 0) return 0.0;
  if (problem.storage == DelassusStorage::sparse) return sparse_residual(problem, r);
  Eigen::MatrixXd transpose;
  return relative_residual(problem, rows_of(problem.W, transpose), r);
}

}  // namespace csim
