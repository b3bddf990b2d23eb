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
  // The rows of Y that some column reaches, scaled by D^-1/2 (D > 0: a positive definite factor).
  reached_.assign(n, 0);
  for (int c = 0; c < m; ++c)
    for (int i = 0; i < n; ++i) reached_[i] |= Y_(i, c) != 0.0;
  rows_.clear();
  for (int i = 0; i < n; ++i)
    if (reached_[i]) rows_.push_back(i);
  const Vector& D = factor_.vectorD();
  compact_.resize(static_cast<Eigen::Index>(rows_.size()), m);
  for (int k = 0; k < static_cast<int>(rows_.size()); ++k) compact_.row(k) = Y_.row(rows_[k]) / std::sqrt(D(rows_[k]));
  W.noalias() = compact_.transpose() * compact_;
}

}  // namespace csim
