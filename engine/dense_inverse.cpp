#include "engine/dense_inverse.h"

#include <cmath>

namespace csim {

bool invert_positive_definite(const Matrix& A, Matrix& factor, Matrix& inverse) {
  const Eigen::Index n = A.rows();
  factor.resize(n, n);
  inverse.resize(n, n);
  Matrix& L = factor;  // lower triangle: L, then L⁻¹ in place
  for (Eigen::Index j = 0; j < n; ++j) {
    double pivot = A(j, j);
    for (Eigen::Index k = 0; k < j; ++k) pivot -= L(j, k) * L(j, k);
    if (!(pivot > 0.0)) return false;
    L(j, j) = std::sqrt(pivot);
    for (Eigen::Index i = j + 1; i < n; ++i) {
      double sum = A(i, j);
      for (Eigen::Index k = 0; k < j; ++k) sum -= L(i, k) * L(j, k);
      L(i, j) = sum / L(j, j);
    }
  }
  // X = L⁻¹ into inverse's lower triangle, column by column (forward substitution of e_j).
  for (Eigen::Index j = 0; j < n; ++j) {
    inverse(j, j) = 1.0 / L(j, j);
    for (Eigen::Index i = j + 1; i < n; ++i) {
      double sum = 0.0;
      for (Eigen::Index k = j; k < i; ++k) sum -= L(i, k) * inverse(k, j);
      inverse(i, j) = sum / L(i, i);
    }
  }
  // A⁻¹(i, j) = Σ_{k ≥ max(i, j)} X(k, i) X(k, j).
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = j; i < n; ++i) {
      double sum = 0.0;
      for (Eigen::Index k = i; k < n; ++k) sum += inverse(k, i) * inverse(k, j);
      L(i, j) = sum;  // L's lower triangle is free now: A⁻¹'s lower triangle goes there first
    }
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = j; i < n; ++i) inverse(i, j) = inverse(j, i) = L(i, j);
  return true;
}

}  // namespace csim
