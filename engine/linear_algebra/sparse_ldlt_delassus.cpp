// SparseLdlt's forward columns and Delassus operator (sparse_ldlt.h): the elimination tree, a sparse
// column y = L⁻¹ P hᵀ by the reach of h's nonzeros (Gilbert & Peierls 1988), the products of such
// columns (an entry y_aᵀ D⁻¹ y_b of W), and W = H_S G H_Sᵀ with G = Yᵀ D⁻¹ Y of the unknowns S.
#include "engine/linear_algebra/sparse_ldlt_storage.h"

#include <algorithm>
#include <cmath>

namespace csim {

// The parent of each column of L in the elimination tree (its first subdiagonal row: L's columns are
// sorted, and the smallest row is taken whatever the order) and the pivots D.
void SparseLdlt::prepare_tree() const {
  if (tree_ready_) return;
  const Cholmod& c = *cholmod_;
  const int n = size();
  if (!ours_) {  // CHOLMOD's forward columns need no tree
    cholmod_pivots(pivots_, false);
    tree_ready_ = true;
    return;
  }
  const int* start = c.column_start();
  const int* count = c.column_count();
  const int* row = c.row_index();
  const double* x = c.values();
  parent_.assign(n, -1);
  pivots_.resize(n);
  for (int j = 0; j < n; ++j) {
    pivots_(j) = x[start[j]];
    int first = n;
    for (int q = start[j] + 1; q < start[j] + count[j]; ++q) first = std::min(first, row[q]);
    if (first < n) parent_[j] = first;
  }
  if (static_cast<int>(mark_.size()) != n) mark_.assign(n, 0);
  work_.setZero(n);
  tree_ready_ = true;
}

void SparseLdlt::forward(const int* index, const double* value, int count, ForwardColumn& y) const {
  prepare_tree();
  if (!ours_) return forward_by_cholmod(index, value, count, y);
  const Cholmod& c = *cholmod_;
  // The reach: every column on the paths from the right-hand side's nonzeros to the root (marks are
  // cleared on the way out, so that the next call starts from zero), in ascending order, so that a
  // column's ancestors come after it. Each path ascends (a parent comes after its child), so that the
  // reach is the merge of the new part of each path into the reach so far, where a sort of the whole
  // took a ninth of the time of a column at 13k unknowns (bench_factor's forward table).
  reach_.clear();
  for (int k = 0; k < count; ++k) {
    int j = c.inverse[index[k]];
    work_(j) += value[k];
    const std::size_t before = reach_.size();
    for (; j >= 0 && !mark_[j]; j = parent_[j]) {
      mark_[j] = 1;
      reach_.push_back(j);
    }
    if (before > 0 && reach_.size() > before) {
      merged_.resize(reach_.size());
      std::merge(reach_.begin(), reach_.begin() + static_cast<std::ptrdiff_t>(before), reach_.begin() + static_cast<std::ptrdiff_t>(before),
                 reach_.end(), merged_.begin());
      reach_.swap(merged_);
    }
  }
  const int* start = c.column_start();
  const int* column_count = c.column_count();
  const int* row = c.row_index();
  const double* x = c.values();
  y.index.resize(reach_.size());
  y.value.resize(reach_.size());
  for (std::size_t k = 0; k < reach_.size(); ++k) {
    const int j = reach_[k];
    const double yj = work_(j);
    for (int q = start[j] + 1; q < start[j] + column_count[j]; ++q) work_(row[q]) -= x[q] * yj;
    y.index[k] = j;
    y.value[k] = yj;
    work_(j) = 0.0;
    mark_[j] = 0;
  }
}

double SparseLdlt::delassus_entry(const ForwardColumn& a, const ForwardColumn& b) const {
  double sum = 0.0;
  std::size_t p = 0, q = 0;
  while (p < a.index.size() && q < b.index.size()) {
    if (a.index[p] < b.index[q]) {
      ++p;
    } else if (b.index[q] < a.index[p]) {
      ++q;
    } else {
      sum += a.value[p] * b.value[q] / pivots_(a.index[p]);
      ++p;
      ++q;
    }
  }
  return sum;
}

const Vector& SparseLdlt::pivots() const {
  prepare_tree();
  return pivots_;
}

void SparseLdlt::scatter_scaled(const ForwardColumn& y, Vector& x) const {
  for (std::size_t k = 0; k < y.index.size(); ++k) x(y.index[k]) = y.value[k] / pivots_(y.index[k]);
}

double SparseLdlt::dot(const ForwardColumn& y, const Vector& x) {
  double sum = 0.0;
  for (std::size_t k = 0; k < y.index.size(); ++k) sum += y.value[k] * x(y.index[k]);
  return sum;
}

void SparseLdlt::add_scaled(double a, const ForwardColumn& y, Vector& x) {
  for (std::size_t k = 0; k < y.index.size(); ++k) x(y.index[k]) += a * y.value[k];
}

// G = E_Sᵀ A⁻¹ E_S for the unknowns S that H's rows touch, from their unit forward columns, and then
// W = H_S G H_Sᵀ (see the header).
void SparseLdlt::delassus(const Matrix& H, Matrix& W) {
  const int m = static_cast<int>(H.rows()), n = static_cast<int>(H.cols());
  W.resize(m, m);
  if (m == 0) return;
  touched_.clear();
  for (int k = 0; k < n; ++k)
    for (int a = 0; a < m; ++a)
      if (H(a, k) != 0.0) {
        touched_.push_back(k);
        break;
      }
  const int s = static_cast<int>(touched_.size());
  if (gram_factorization_ == factorizations_ && touched_ == unknowns_) {
    ++kept_delassus_;
  } else {
    std::swap(unknowns_, touched_);
    inverse_block();
    gram_factorization_ = factorizations_;
  }
  rows_on_unknowns_.resize(m, s);
  for (int j = 0; j < s; ++j) rows_on_unknowns_.col(j) = H.col(unknowns_[j]);
  rows_times_block_.noalias() = rows_on_unknowns_ * gram_;
  // The lower triangle, mirrored: W symmetric to the bit, as the contact solvers read it.
  for (int b = 0; b < m; ++b)
    for (int a = b; a < m; ++a) W(a, b) = W(b, a) = rows_times_block_.row(a).dot(rows_on_unknowns_.row(b));
}

// gram_ ← E_Sᵀ A⁻¹ E_S = Yᵀ D⁻¹ Y, Y = L⁻¹ P E_S, S = unknowns_: each column of Y is the forward
// substitution of one unknown, which fills only that unknown's path to the root of the elimination tree.
void SparseLdlt::inverse_block() {
  const int n = size(), s = static_cast<int>(unknowns_.size());
  gram_.resize(s, s);
  // Y's sparse columns, and Y_ dense, which is zero between calls (the entries written are cleared at the
  // end, not all n × s).
  if (Y_.rows() != n || Y_.cols() < s) Y_.setZero(n, std::max<Eigen::Index>(s, Y_.cols()));
  columns_.resize(s);
  const double one = 1.0;
  for (int c = 0; c < s; ++c) {
    forward(&unknowns_[c], &one, 1, columns_[c]);
    for (std::size_t k = 0; k < columns_[c].index.size(); ++k) Y_(columns_[c].index[k], c) = columns_[c].value[k];
  }
  // The columns that reach each row of Y with a nonzero, in column order, from the sparse columns.
  row_start_.assign(n + 1, 0);
  for (int c = 0; c < s; ++c)
    for (std::size_t k = 0; k < columns_[c].index.size(); ++k)
      if (columns_[c].value[k] != 0.0) ++row_start_[columns_[c].index[k] + 1];
  for (int i = 0; i < n; ++i) row_start_[i + 1] += row_start_[i];
  row_columns_.resize(row_start_[n]);
  fill_.assign(row_start_.begin(), row_start_.end() - 1);
  for (int c = 0; c < s; ++c)
    for (std::size_t k = 0; k < columns_[c].index.size(); ++k)
      if (columns_[c].value[k] != 0.0) row_columns_[fill_[columns_[c].index[k]]++] = c;
  // G = Σ_i y_i y_iᵀ / D_i over the rows y_i of Y (D > 0: a positive definite factor). A row that few
  // columns reach (below the top separators of the elimination tree) adds its few products directly; the
  // denser rows, scaled by D^-1/2, go to one matrix product.
  const Vector& D = pivots_;
  gram_.setZero();
  rows_.clear();
  for (int i = 0; i < n; ++i) {
    const int* columns = row_columns_.data() + row_start_[i];
    const int k = row_start_[i + 1] - row_start_[i];
    if (k == 0) continue;
    if (3 * k > s) {
      rows_.push_back(i);
      continue;
    }
    for (int p = 0; p < k; ++p) {
      const double scaled = Y_(i, columns[p]) / D(i);
      for (int q = 0; q <= p; ++q) gram_(columns[q], columns[p]) += scaled * Y_(i, columns[q]);
    }
  }
  compact_.resize(static_cast<Eigen::Index>(rows_.size()), s);
  for (int k = 0; k < static_cast<int>(rows_.size()); ++k)
    compact_.row(k) = Y_.row(rows_[k]).head(s) / std::sqrt(D(rows_[k]));
  gram_.triangularView<Eigen::StrictlyLower>() = gram_.transpose().triangularView<Eigen::StrictlyLower>();
  gram_.noalias() += compact_.transpose() * compact_;
  for (int c = 0; c < s; ++c)
    for (int i : columns_[c].index) Y_(i, c) = 0.0;
}

}  // namespace csim
