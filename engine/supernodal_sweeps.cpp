#include "engine/supernodal_sweeps.h"

#include <Eigen/Core>

#include <algorithm>

namespace csim {

namespace {

// How far ahead of its reads the backward sweep prefetches the storage (docs/solver-measurements.md,
// ninth round).
constexpr long kPrefetchBytes = 8192;

using Column = Eigen::Map<Eigen::VectorXd>;
using ConstColumn = Eigen::Map<const Eigen::VectorXd>;

// Σ_i a_i x[rows_i] in four independent sums, so that a long column is not one chain of dependent
// additions (the latency that bounds a column-by-column sweep).
double gathered_dot(const double* a, const int* rows, int m, const double* x) {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  int i = 0;
  for (; i + 4 <= m; i += 4) {
    s0 += a[i] * x[rows[i]];
    s1 += a[i + 1] * x[rows[i + 1]];
    s2 += a[i + 2] * x[rows[i + 2]];
    s3 += a[i + 3] * x[rows[i + 3]];
  }
  for (; i < m; ++i) s0 += a[i] * x[rows[i]];
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
  int rows = 0, columns = 0;
  for (int s = 0; s < supernodes(); ++s) {
    rows = std::max(rows, below_start_[s + 1] - below_start_[s]);
    columns = std::max(columns, first_column_[s + 1] - first_column_[s]);
  }
  work_.assign(rows, 0.0);
  dots_.assign(columns, 0.0);
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

// The supernodes from the last; within one, the dots below the diagonal block (independent of each other:
// x there is final) in the storage's order, then the diagonal block from its last column.
void SupernodalSweeps::backward(const int* start, const double* values, double* x) const {
  long prefetched = supernodes() == 0 ? 0 : static_cast<long>(start[first_column_.back() - 1]) * 8;  // bytes from values
  for (int s = supernodes() - 1; s >= 0; --s) {
    const int c0 = first_column_[s], w = first_column_[s + 1] - c0;
    const int* below = below_.data() + below_start_[s];
    const int m = below_start_[s + 1] - below_start_[s];
    // The storage is read from its end, a stream the hardware does not prefetch well: the bytes below
    // the supernode are asked for ahead.
    for (const long target = std::max(0L, static_cast<long>(start[c0]) * 8 - kPrefetchBytes); prefetched > target;) {
      prefetched -= 64;
      __builtin_prefetch(reinterpret_cast<const char*>(values) + prefetched);
    }
    if (w == 1) {
      const double* column = values + start[c0];
      x[c0] = x[c0] / column[0] - gathered_dot(column + 1, below, m, x);
      continue;
    }
    Column gathered(work_.data(), m);
    for (int i = 0; i < m; ++i) gathered[i] = x[below[i]];
    for (int k = 0; k < w; ++k) dots_[k] = ConstColumn(values + start[c0 + k] + w - k, m).dot(gathered);
    for (int k = w - 1; k >= 0; --k) {
      const double* column = values + start[c0 + k];
      const double block_sum = ConstColumn(column + 1, w - 1 - k).dot(ConstColumn(x + c0 + k + 1, w - 1 - k));
      x[c0 + k] = x[c0 + k] / column[0] - (block_sum + dots_[k]);
    }
  }
}

}  // namespace csim
