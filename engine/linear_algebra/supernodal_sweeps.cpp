#include "engine/linear_algebra/supernodal_sweeps.h"

#include <Eigen/Core>

#include <algorithm>

namespace csim {

namespace {

using Column = Eigen::Map<Eigen::VectorXd>;
using ConstColumn = Eigen::Map<const Eigen::VectorXd>;

// Σ_i a_i b_i from the last i down, in two packets of two: the backward sweep reads the storage from
// its end, and each of its dots reads its column the same way.
double descending_dot(const double* a, const double* b, int m) {
  using Pair = Eigen::Map<const Eigen::Vector2d>;
  Eigen::Vector2d upper = Eigen::Vector2d::Zero(), lower = upper;
  int i = m;
  for (; i >= 4; i -= 4) {
    upper += Pair(a + i - 2).cwiseProduct(Pair(b + i - 2));
    lower += Pair(a + i - 4).cwiseProduct(Pair(b + i - 4));
  }
  const Eigen::Vector2d sum = upper + lower;
  double dot = sum[0] + sum[1];
  for (; i > 0; --i) dot += a[i - 1] * b[i - 1];
  return dot;
}

// Σ_i a_i x[rows_i] from the last i down, in four independent sums, so that a long column is not one
// chain of dependent additions (the latency that bounds a column-by-column sweep).
double descending_gathered_dot(const double* a, const int* rows, int m, const double* x) {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  int i = m;
  for (; i >= 4; i -= 4) {
    s0 += a[i - 1] * x[rows[i - 1]];
    s1 += a[i - 2] * x[rows[i - 2]];
    s2 += a[i - 3] * x[rows[i - 3]];
    s3 += a[i - 4] * x[rows[i - 4]];
  }
  for (; i > 0; --i) s0 += a[i - 1] * x[rows[i - 1]];
  return (s0 + s1) + (s2 + s3);
}

}  // namespace

void SupernodalSweeps::analyse(int n, const int* start, const int* count, const int* row) {
  first_column_.clear();
  below_start_.clear();
  below_.clear();
  int j = 0;
  while (j < n) {
    int last = j;  // the supernode's last column
    while (last + 1 < n && count[last] >= 2 && row[start[last] + 1] == last + 1 && count[last + 1] == count[last] - 1 &&
           std::equal(row + start[last] + 1, row + start[last] + count[last], row + start[last + 1]))
      ++last;
    first_column_.push_back(j);
    below_start_.push_back(static_cast<int>(below_.size()));
    const int w = last - j + 1;
    below_.insert(below_.end(), row + start[j] + w, row + start[j] + count[j]);
    j = last + 1;
  }
  first_column_.push_back(n);
  below_start_.push_back(static_cast<int>(below_.size()));
  int rows = 0;
  for (int s = 0; s < supernodes(); ++s) rows = std::max(rows, below_start_[s + 1] - below_start_[s]);
  work_.assign(rows, 0.0);
}

// Each supernode's storage is read once, in the order it lies: column by column, each column's entries in
// the diagonal block, then below it.
void SupernodalSweeps::forward(const int* start, const double* values, double* x) const {
  for (int s = 0; s < supernodes(); ++s) {
    const int c0 = first_column_[s], w = first_column_[s + 1] - c0;
    const int* below = below_.data() + below_start_[s];
    const int m = below_start_[s + 1] - below_start_[s];
    if (w == 1) {
      const double x0 = x[c0];
      const double* column = values + start[c0] + 1;
      for (int i = 0; i < m; ++i) x[below[i]] -= column[i] * x0;
      continue;
    }
    // The block below the diagonal times the supernode's x, summed over its columns, then subtracted;
    // x_k is final once the columns before k have updated the diagonal block.
    Column sum(work_.data(), m);
    sum.setZero();
    for (int k = 0; k < w; ++k) {
      const double xk = x[c0 + k];
      const double* column = values + start[c0 + k] + 1;
      Column(x + c0 + k + 1, w - 1 - k).noalias() -= xk * ConstColumn(column, w - 1 - k);
      sum.noalias() += xk * ConstColumn(column + w - 1 - k, m);
    }
    for (int i = 0; i < m; ++i) x[below[i]] -= sum[i];
  }
}

// The supernodes from the last; within one, its columns from the last, each read from its end (the rows
// below the diagonal block, then the block, then D_j): the whole sweep reads the storage in descending
// order, a stream the hardware prefetches as it does the forward sweep's (docs/solver-measurements.md). x below the supernode is final, and x_k once the supernode's columns after k are.
void SupernodalSweeps::backward(const int* start, const double* values, double* x) const {
  for (int s = supernodes() - 1; s >= 0; --s) {
    const int c0 = first_column_[s], w = first_column_[s + 1] - c0;
    const int* below = below_.data() + below_start_[s];
    const int m = below_start_[s + 1] - below_start_[s];
    if (w == 1) {
      const double* column = values + start[c0];
      x[c0] = x[c0] / column[0] - descending_gathered_dot(column + 1, below, m, x);
      continue;
    }
    double* gathered = work_.data();
    for (int i = m - 1; i >= 0; --i) gathered[i] = x[below[i]];
    for (int k = w - 1; k >= 0; --k) {
      const double* column = values + start[c0 + k];
      const double below_sum = descending_dot(column + w - k, gathered, m);
      const double block_sum = descending_dot(column + 1, x + c0 + k + 1, w - 1 - k);
      x[c0 + k] = x[c0 + k] / column[0] - (block_sum + below_sum);
    }
  }
}

}  // namespace csim
