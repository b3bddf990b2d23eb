// A Gauss–Seidel sweep of PgsSolver's dense path (pgs_solver.h, dense_pgs.h), in a header so that the
// iteration (pgs_iteration.h, run by pgs_solver.cpp) inlines it: on a few contacts a sweep is a few
// hundred instructions, and out of line it cost 1 % more instructions a step of a lumped scene
// (bench/step_instructions.sh).
// Internal to contact/.
#pragma once

#include "contact/dense_pgs.h"
#include "contact/pgs_local.h"

namespace csim::dense_pgs {

using pgs_local::Matrix;
using pgs_local::Vector;

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

// One sweep over the contacts in row order (D the contact dimension); `rejected` counts the non-finite
// local results filtered out. W_rows: rows_of(problem.W).
template <int D>
[[gnu::always_inline]] inline SweepResult sweep(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows,
                                                const PgsParameters& parameters, Eigen::VectorXd& r, int& rejected) {
  SweepResult result;
  for (int c = 0; c < problem.contacts; ++c) {
    const Eigen::Index first = static_cast<Eigen::Index>(D) * c;
    pgs_local::update_contact<D>(c, problem.W.template block<D, D>(first, first), frozen_free_velocity<D>(problem, W_rows, r, first),
                      problem.b.template segment<D>(first), problem.mu[c], parameters.omega, r.data() + first, result,
                      rejected);
  }
  return result;
}

}  // namespace csim::dense_pgs
