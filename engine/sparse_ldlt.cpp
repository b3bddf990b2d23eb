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
  Y_.noalias() = factor_.permutationP() * H.transpose();
  factor_.matrixL().solveInPlace(Y_);
  // W = Σ_i y_i y_iᵀ / D_i over the rows y_i of Y (D > 0: a positive definite factor). A row that few
  // columns reach (below the top separators of the elimination tree) adds its few products directly; the
  // denser rows, scaled by D^-1/2, go to one matrix product.
  const Vector& D = factor_.vectorD();
  W.setZero();
  rows_.clear();
  for (int i = 0; i < n; ++i) {
    columns_.clear();
    for (int c = 0; c < m; ++c)
      if (Y_(i, c) != 0.0) columns_.push_back(c);
    const int k = static_cast<int>(columns_.size());
    if (k == 0) continue;
    if (3 * k > m) {
      rows_.push_back(i);
      continue;
    }
    for (int p = 0; p < k; ++p) {
      const double scaled = Y_(i, columns_[p]) / D(i);
      for (int q = 0; q <= p; ++q) W(columns_[q], columns_[p]) += scaled * Y_(i, columns_[q]);
    }
  }
  compact_.resize(static_cast<Eigen::Index>(rows_.size()), m);
  for (int k = 0; k < static_cast<int>(rows_.size()); ++k) compact_.row(k) = Y_.row(rows_[k]) / std::sqrt(D(rows_[k]));
  W.triangularView<Eigen::StrictlyLower>() = W.transpose().triangularView<Eigen::StrictlyLower>();
  W.noalias() += compact_.transpose() * compact_;
}

}  // namespace csim
