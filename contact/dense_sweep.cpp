// A Gauss–Seidel sweep and the full residual of PgsSolver's dense path (pgs_solver.h, dense_pgs.h).
#include "contact/dense_sweep.h"

#include <algorithm>
#include <cmath>
#include <limits>

// Implementation notes.
// - The coupling of contact c with the others is W's rows c (u = W r + b), read as the contiguous
//   columns of a matrix `W_rows` whose column i is W's row i (Eigen stores by column): W itself when W
//   is symmetric to the bit (every Delassus the steppers form), else Wᵀ, copied once per solve
//   (rows_of). A row read down a column-major W strides by its size, several times slower. A W
//   symmetric to round-off (symmetry_of) is swept on its own columns, and its residual formed from
//   W r by columns (relative_residual_by_columns), which reads W as stored: pgs_solver.cpp.
// - Per-contact work is templated on the contact dimension and uses fixed-size Eigen objects: a solve
//   without equality rows does not allocate at all; with equalities the condensed problem's arrays are
//   the solver's (PgsCondensation), reused from solve to solve.

namespace csim::dense_pgs {
namespace {

using pgs_local::Matrix;
using pgs_local::Vector;
using pgs_local::law_term;
using pgs_local::velocity_scale;

// ‖(W r)_c‖², (m/s)², of the contact whose rows start at `first`, from its frozen velocity (above) and
// its impulse r_c: (frozen − b_c) + W_cc r_c.
template <int D>
double product_squared(const FrictionContactProblem& problem, Eigen::Index first, const Vector<D>& frozen,
                       const Matrix<D>& W_cc, const Vector<D>& r_c) {
  return (frozen - problem.b.template segment<D>(first) + W_cc * r_c).squaredNorm();
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
    const double term = law_term<D>(W_cc, b_c, problem.mu[c], r_c);
    sums.law += term;
    if (std::isinf(term)) return;
  }
}

// add_contact_sums' terms from the product W r (relative_residual_by_columns), every contact's.
template <int D>
void add_contact_sums_by_columns(const FrictionContactProblem& problem, const Eigen::VectorXd& r,
                                 const Eigen::VectorXd& product, ResidualSums& sums) {
  for (int c = 0; c < problem.contacts; ++c) {
    const Eigen::Index first = static_cast<Eigen::Index>(D) * c;
    const Matrix<D> W_cc = problem.W.template block<D, D>(first, first);
    const Vector<D> r_c = r.template segment<D>(first);
    const Vector<D> Wr_c = product.template segment<D>(first);
    const Vector<D> b_c = problem.b.template segment<D>(first) + (Wr_c - W_cc * r_c);
    sums.product += Wr_c.squaredNorm();
    const double term = law_term<D>(W_cc, b_c, problem.mu[c], r_c);
    sums.law += term;
    if (std::isinf(term)) return;
  }
}

}  // namespace

bool is_symmetric(const Eigen::MatrixXd& W) {
  const Eigen::Index m = W.rows();
  for (Eigen::Index j = 0; j < m; ++j)
    for (Eigen::Index i = j + 1; i < m; ++i)
      if (W(i, j) != W(j, i)) return false;
  return true;
}

// First to the bit, as is_symmetric, to the first unequal pair: a W formed symmetric (every stepper's)
// costs no more than that test did. From that pair's two columns on, W's 2 × 2 tiles below the
// diagonal, columns j, j + 1 against rows j, j + 1: each side read as two contiguous pairs of entries
// (one vector load each), the rows' pair transposed in registers; a loop over single pairs reads one of
// each across W's column stride, and cost 15 instructions a pair on NESpheres_30_1, more than the copy
// of Wᵀ it is there to spare. The largest skew is kept, and the sum of all, which a NaN (lost by a
// maximum) or an overflow makes non-finite: such a W is not near symmetric. The bound is tested after
// each pair of columns, so that an unsymmetric W stops early.
Symmetry symmetry_of(const Eigen::MatrixXd& W) {
  const Eigen::Index m = W.rows();
  Eigen::Index unequal = m;  // the column of the first unequal pair
  for (Eigen::Index j = 0; j < m && unequal == m; ++j)
    for (Eigen::Index i = j + 1; i < m; ++i)
      if (W(i, j) != W(j, i)) {
        unequal = j;
        break;
      }
  if (unequal == m) return Symmetry::exact;

  using Pair = Eigen::Array2d;
  const double bound = kNearSymmetry * W.diagonal().cwiseAbs().maxCoeff();
  Pair largest = Pair::Zero(), sum = Pair::Zero();
  const auto add_one = [&](Eigen::Index i, Eigen::Index j) {
    const double skew = std::abs(W(i, j) - W(j, i));
    largest(0) = std::max(largest(0), skew);
    sum(0) += skew;
  };
  const Eigen::Index even = m - m % 2;
  for (Eigen::Index j = unequal - unequal % 2; j < even; j += 2) {
    add_one(j + 1, j);
    for (Eigen::Index i = j + 2; i < even; i += 2) {
      const double* row_j = &W(j, i);          // W(j, i), W(j + 1, i)
      const double* row_j_next = &W(j, i + 1);  // W(j, i + 1), W(j + 1, i + 1)
      const Pair first = (Eigen::Map<const Pair>(&W(i, j)) - Pair(row_j[0], row_j_next[0])).abs();
      const Pair second = (Eigen::Map<const Pair>(&W(i, j + 1)) - Pair(row_j[1], row_j_next[1])).abs();
      largest = largest.max(first).max(second);
      sum += first + second;
    }
    if (even < m) {
      add_one(m - 1, j);
      add_one(m - 1, j + 1);
    }
    if (!(largest.maxCoeff() <= bound) || !std::isfinite(sum.sum())) return Symmetry::none;
  }
  return Symmetry::near;
}

const Eigen::MatrixXd& rows_of(const Eigen::MatrixXd& W, Eigen::MatrixXd& transpose) {
  if (is_symmetric(W)) return W;
  transpose.noalias() = W.transpose();
  return transpose;
}

double relative_residual(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, const Eigen::VectorXd& r,
                         int settled_from) {
  ResidualSums sums;
  add_equality_sums(problem, W_rows, r, sums);
  if (problem.dimension == 2) add_contact_sums<2>(problem, W_rows, r, settled_from, sums);
  else add_contact_sums<3>(problem, W_rows, r, settled_from, sums);
  const double residual = std::sqrt(sums.law) / velocity_scale(problem.b.norm(), std::sqrt(sums.product));
  return std::isnan(residual) ? std::numeric_limits<double>::infinity() : residual;
}

double relative_residual_by_columns(const FrictionContactProblem& problem, const Eigen::VectorXd& r,
                                    Eigen::VectorXd& product) {
  // A column at a time (an axpy each), not Eigen's general product: on a few contacts its set-up and
  // its code, new to a solve that otherwise never calls it, cost more than the product itself. The
  // columns of zero impulses (open contacts) are skipped: exact, W's off-diagonal entries being finite
  // where this residual is used (symmetry_of's near; a non-finite diagonal entry still makes the
  // contact's W_cc r_c, hence the residual, non-finite).
  // The first column assigned rather than a zeroed vector added to: setZero calls memset, whose first
  // call in a process (resolving its symbol) cost 1300 instructions, a sixth of a 6-contact solve.
  const Eigen::Index m = problem.size();
  product.noalias() = problem.W.col(0) * r(0);
  for (Eigen::Index j = 1; j < m; ++j)
    if (r(j) != 0.0) product.noalias() += problem.W.col(j) * r(j);
  ResidualSums sums;
  const Eigen::Index m_c = static_cast<Eigen::Index>(problem.dimension) * problem.contacts;
  for (Eigen::Index j = m_c; j < problem.size(); ++j) {
    const double u_j = product(j) + problem.b(j);
    sums.law += u_j * u_j;
    sums.product += product(j) * product(j);
  }
  if (problem.dimension == 2) add_contact_sums_by_columns<2>(problem, r, product, sums);
  else add_contact_sums_by_columns<3>(problem, r, product, sums);
  const double residual = std::sqrt(sums.law) / velocity_scale(problem.b.norm(), std::sqrt(sums.product));
  return std::isnan(residual) ? std::numeric_limits<double>::infinity() : residual;
}

double relative_residual(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, const Eigen::VectorXd& r) {
  return relative_residual(problem, W_rows, r, problem.contacts);
}

}  // namespace csim::dense_pgs
