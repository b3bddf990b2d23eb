#include "engine/linear_algebra/dense_inverse.h"

#include <cmath>

namespace csim {

namespace {

// The same arithmetic, in the same order, for every size: a compiled size (3, 6) works in local
// arrays with its loops unrolled, and its result is the dynamic size's to the bit.
template <int N>
struct Square {
  double value[N][N];
  explicit Square(Matrix&) {}
  double& operator()(Eigen::Index i, Eigen::Index j) { return value[i][j]; }
};
template <>
struct Square<Eigen::Dynamic> {
  Matrix& value;
  explicit Square(Matrix& m) : value(m) {}
  double& operator()(Eigen::Index i, Eigen::Index j) { return value(i, j); }
};

template <int N, class Factor, class Inverse>
bool invert(const Matrix& A, Eigen::Index n, Factor& L, Inverse& inverse) {
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
  return true;
}

template <int N>
bool invert_sized(const Matrix& A, Matrix& factor, Matrix& inverse) {
  const Eigen::Index n = N == Eigen::Dynamic ? A.rows() : N;
  Square<N> L(factor), X(inverse);
  if (!invert<N>(A, n, L, X)) return false;
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = j; i < n; ++i) inverse(i, j) = inverse(j, i) = L(i, j);
  return true;
}

}  // namespace

bool invert_positive_definite(const Matrix& A, Matrix& factor, Matrix& inverse) {
  const Eigen::Index n = A.rows();
  factor.resize(n, n);
  inverse.resize(n, n);
  switch (n) {
    case 3: return invert_sized<3>(A, factor, inverse);
    case 6: return invert_sized<6>(A, factor, inverse);
    default: return invert_sized<Eigen::Dynamic>(A, factor, inverse);
  }
}

}  // namespace csim
