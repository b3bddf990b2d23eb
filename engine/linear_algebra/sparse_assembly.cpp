#include "engine/linear_algebra/sparse_assembly.h"

#include <algorithm>
#include <stdexcept>

namespace csim {

bool same_pattern(const SparseMatrix& a, const SparseMatrix& b) {
  return a.isCompressed() && b.isCompressed() && a.rows() == b.rows() && a.cols() == b.cols() &&
         a.nonZeros() == b.nonZeros() &&
         std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.cols() + 1, b.outerIndexPtr()) &&
         std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr());
}

void SparseAssembly::record(int row, int column, double value) {
  replay_ = false;  // the entries before count_ are still the stream's: they are kept
  if (count_ < row_.size()) {
    row_[count_] = row;
    column_[count_] = column;
    value_[count_] = value;
  } else {
    row_.push_back(row);
    column_.push_back(column);
    value_.push_back(value);
  }
  ++count_;
}

// Each column's rows sorted, duplicates one slot: by a stable counting sort on the row, then on the
// column, so that the entries of a slot stay in the order they came.
void SparseAssembly::build_pattern(int rows, int columns) {
  const std::size_t n = count_;
  row_.resize(n);
  column_.resize(n);
  value_.resize(n);
  std::vector<int> start(std::max(rows, columns) + 1), by_row(n), order(n);
  std::fill(start.begin(), start.end(), 0);
  for (std::size_t k = 0; k < n; ++k) ++start[row_[k] + 1];
  for (int i = 0; i < rows; ++i) start[i + 1] += start[i];
  for (std::size_t k = 0; k < n; ++k) by_row[start[row_[k]]++] = static_cast<int>(k);
  std::fill(start.begin(), start.end(), 0);
  for (std::size_t k = 0; k < n; ++k) ++start[column_[k] + 1];
  for (int j = 0; j < columns; ++j) start[j + 1] += start[j];
  std::vector<int> outer(start.begin(), start.begin() + columns + 1);
  for (int k : by_row) order[start[column_[k]]++] = k;
  // order: column-major, rows ascending, each position's entries in stream order.
  slot_.resize(n);
  std::vector<int> inner;
  inner.reserve(n);
  std::vector<int> outer_compressed(columns + 1, 0);
  for (int j = 0; j < columns; ++j) {
    outer_compressed[j] = static_cast<int>(inner.size());
    int last = -1;
    for (int p = outer[j]; p < outer[j + 1]; ++p) {
      const int k = order[p];
      if (row_[k] != last) {
        inner.push_back(row_[k]);
        last = row_[k];
      }
      slot_[k] = static_cast<int>(inner.size()) - 1;
    }
  }
  outer_compressed[columns] = static_cast<int>(inner.size());
  pattern_.resize(rows, columns);
  pattern_.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
  std::copy(outer_compressed.begin(), outer_compressed.end(), pattern_.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), pattern_.innerIndexPtr());
  std::fill(pattern_.valuePtr(), pattern_.valuePtr() + inner.size(), 0.0);
  rows_ = rows;
  columns_ = columns;
  patterned_ = true;
  ++patterns_;
}

void SparseAssembly::resume(std::size_t count, const std::vector<double>& sums) {
  if (!patterned_ || count_ != 0 || count > row_.size() || sums.size() != nonzeros())
    throw std::logic_error("SparseAssembly::resume without the last assembly's pattern");
  count_ = count;
  leading_count_ = count;
  leading_ = &sums;
}

bool SparseAssembly::finish(int rows, int columns, SparseMatrix& matrix) {
  const bool rebuilt = !replay_ || count_ != row_.size() || rows != rows_ || columns != columns_;
  // The resumed entries' sums are by their slot in the last pattern: kept to move them to the new one.
  if (rebuilt && leading_count_ > 0) leading_slot_.assign(slot_.begin(), slot_.begin() + leading_count_);
  if (rebuilt) build_pattern(rows, columns);
  // matrix keeps the pattern unless someone changed it since (then it gets it again).
  const Eigen::Index nonzeros = pattern_.nonZeros();
  if (!same_pattern(matrix, pattern_)) matrix = pattern_;
  double* values = matrix.valuePtr();
  std::size_t k = 0;
  if (leading_count_ > 0 && !rebuilt) {
    std::copy(leading_->begin(), leading_->end(), values);
    k = leading_count_;
  } else {
    std::fill(values, values + nonzeros, 0.0);
    // Each slot's resumed entries precede its others in the stream: its sum first, then theirs.
    for (; k < leading_count_; ++k) values[slot_[k]] = (*leading_)[leading_slot_[k]];
  }
  for (; k < count_; ++k) values[slot_[k]] += value_[k];
  leading_count_ = 0;
  leading_ = nullptr;
  return rebuilt;
}

}  // namespace csim
