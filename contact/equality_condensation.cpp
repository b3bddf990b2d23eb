// The bilateral rows of PgsSolver's dense path condensed out before the sweeps (pgs_solver.h, dense_pgs.h).
#include "contact/dense_pgs.h"

#include <cmath>
#include <limits>

namespace csim {
namespace dense_pgs {
namespace {

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

}  // namespace

double recovered_residual(const FrictionContactProblem& problem, PgsCondensation& condensed,
                          const Eigen::VectorXd& r_c, Eigen::VectorXd& r, int& rejected) {
  const Eigen::Index m_c = static_cast<Eigen::Index>(problem.dimension) * problem.contacts;
  const Eigen::Index m_e = problem.equalities;
  Eigen::VectorXd& r_e = condensed.r_e;
  Eigen::VectorXd& u_e = condensed.u_e;
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
    ++rejected;
    r_e.setZero();
  }
  r.resize(problem.size());
  r.head(m_c) = r_c;
  r.tail(m_e) = r_e;
  return relative_residual(problem, condensed.symmetric ? problem.W : condensed.W_transpose, r);
}

// Gauss–Seidel on the condensed contact rows, then r_e from r_c, with one step of refinement on the
// equality rows (W_ee's condition number is 2e4 on the 3D ring tied to a light hub). Converged is
// decided on the full problem's residual, at every test of the iteration (solve_condensed_rows).
PgsStatistics solve_with_equalities(const FrictionContactProblem& problem, const PgsParameters& parameters,
                                    Eigen::VectorXd& r, std::vector<ContactStatus>* status,
                                    PgsCondensation& condensed, Eigen::MatrixXd& transpose) {
  const Eigen::Index m_c = static_cast<Eigen::Index>(problem.dimension) * problem.contacts;
  condense(problem, condensed);
  Eigen::VectorXd& r_c = condensed.r_c;
  r_c = r.head(m_c);
  PgsStatistics statistics = solve_condensed_rows(problem, condensed, parameters, r_c, status, transpose);
  statistics.residual = recovered_residual(problem, condensed, r_c, r, statistics.rejected_local_solutions);
  statistics.converged = statistics.residual <= parameters.tolerance;
  return statistics;
}

}  // namespace dense_pgs

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

}  // namespace csim
