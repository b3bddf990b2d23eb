#include "engine/sparse_ldlt.h"

#include <algorithm>
#include <cmath>

namespace csim {

bool SparseLdlt::factor_positive_definite(const SparseMatrix& A) {
  if (!A.isCompressed()) {  // a coeffRef that inserted an entry
    SparseMatrix compressed = A;
    compressed.makeCompressed();
    return factor_positive_definite(compressed);
  }
  const int n = static_cast<int>(A.outerSize()), nnz = static_cast<int>(A.nonZeros());
  const bool same = static_cast<int>(outer_.size()) == n + 1 && static_cast<int>(inner_.size()) == nnz &&
                    std::equal(outer_.begin(), outer_.end(), A.outerIndexPtr()) &&
                    std::equal(inner_.begin(), inner_.end(), A.innerIndexPtr());
  if (!same) {
    factor_.analyzePattern(A);
    outer_.assign(A.outerIndexPtr(), A.outerIndexPtr() + n + 1);
    inner_.assign(A.innerIndexPtr(), A.innerIndexPtr() + nnz);
    ++analyses_;
  }
  factor_.factorize(A);
  return factor_.info() == Eigen::Success && (factor_.vectorD().array() > 0.0).all();
}

void SparseLdlt::delassus(const Matrix& H, Matrix& W) {
  const int m = static_cast<int>(H.rows()), n = static_cast<int>(H.cols());
  W.resize(m, m);
  if (m == 0) return;
  // Y = P Hᵀ from H's nonzeros, H read along its columns (its storage order): on a large mesh the
  // transposing copy, reading H across its columns, took a fifth of this function.
  const auto& permutation = factor_.permutationP().indices();
  Y_.setZero(n, m);
  for (int k = 0; k < n; ++k)
    for (int a = 0; a < m; ++a)
      if (H(a, k) != 0.0) Y_(permutation(k), a) = H(a, k);
  factor_.matrixL().solveInPlace(Y_);
  // The columns that reach each row of Y, gathered along Y's columns (two passes in storage order, not
  // one across them).
  row_start_.assign(n + 1, 0);
  for (int c = 0; c < m; ++c)
    for (int i = 0; i < n; ++i)
      if (Y_(i, c) != 0.0) ++row_start_[i + 1];
  for (int i = 0; i < n; ++i) row_start_[i + 1] += row_start_[i];
  row_columns_.resize(row_start_[n]);
  fill_.assign(row_start_.begin(), row_start_.end() - 1);
  for (int c = 0; c < m; ++c)
    for (int i = 0; i < n; ++i)
      if (Y_(i, c) != 0.0) row_columns_[fill_[i]++] = c;
  // W = Σ_i y_i y_iᵀ / D_i over the rows y_i of Y (D > 0: a positive definite factor). A row that few
  // columns reach (below the top separators of the elimination tree) adds its few products directly; the
  // denser rows, scaled by D^-1/2, go to one matrix product.
  const Vector& D = factor_.vectorD();
  W.setZero();
  rows_.clear();
  for (int i = 0; i < n; ++i) {
    const int* columns = row_columns_.data() + row_start_[i];
    const int k = row_start_[i + 1] - row_start_[i];
    if (k == 0) continue;
    if (3 * k > m) {
      rows_.push_back(i);
      continue;
    }
    for (int p = 0; p < k; ++p) {
      const double scaled = Y_(i, columns[p]) / D(i);
      for (int q = 0; q <= p; ++q) W(columns[q], columns[p]) += scaled * Y_(i, columns[q]);
    }
  }
  compact_.resize(static_cast<Eigen::Index>(rows_.size()), m);
  for (int k = 0; k < static_cast<int>(rows_.size()); ++k) compact_.row(k) = Y_.row(rows_[k]) / std::sqrt(D(rows_[k]));
  W.triangularView<Eigen::StrictlyLower>() = W.transpose().triangularView<Eigen::StrictlyLower>();
  W.noalias() += compact_.transpose() * compact_;
}

}  // namespace csim
