// The dense products of a lumped step (n ≤ StructuralOperators::kDenseLimit unknowns, a dozen contact
// rows), with the common sizes of n (3: a plane rigid body or a point; 6: a rigid body in space)
// compiled for that size: Eigen's dynamic-size kernels cost more in set-up than these products'
// arithmetic, and a fixed size lets a column be unrolled and vectorized.
#pragma once

#include "engine/bodies/body.h"

#include <type_traits>

namespace csim {

namespace small_dense_detail {

template <int N>
using Column = Eigen::Matrix<double, N, 1>;

template <int N>
void multiply(const Matrix& A, const Vector& x, Vector& out) {
  const Eigen::Index n = A.rows();
  out.resize(n);
  Eigen::Map<Column<N>> y(out.data(), n);
  y.setZero();
  for (Eigen::Index j = 0; j < n; ++j) y += x(j) * Eigen::Map<const Column<N>>(A.col(j).data(), n);
}

template <int N>
void combine_columns(const Matrix& A, const Matrix& X, Matrix& G) {
  const Eigen::Index n = A.rows(), m = X.cols();
  G.resize(n, m);
  for (Eigen::Index a = 0; a < m; ++a) {
    Eigen::Map<Column<N>> g(G.col(a).data(), n);
    g.setZero();
    for (Eigen::Index j = 0; j < n; ++j)
      if (X(j, a) != 0.0) g += X(j, a) * Eigen::Map<const Column<N>>(A.col(j).data(), n);
  }
}

template <int N>
void symmetric_gram(const Matrix& X, const Matrix& G, Matrix& W) {
  const Eigen::Index n = X.rows(), m = X.cols();
  W.resize(m, m);
  for (Eigen::Index b = 0; b < m; ++b) {
    const Eigen::Map<const Column<N>> column(G.col(b).data(), n);
    // n = 6 (a rigid body in space): G's column copied, since W's stores may alias G's storage and the
    // map would be read again for every entry; the same values, so the same dot products. Smaller
    // columns cost more to copy than to read again, and a dynamic one would allocate.
    using Kept = std::conditional_t<N == 6, const Column<N>, const Eigen::Map<const Column<N>>&>;
    Kept g = column;
    for (Eigen::Index a = 0; a <= b; ++a) W(a, b) = W(b, a) = Eigen::Map<const Column<N>>(X.col(a).data(), n).dot(g);
  }
}

template <int N>
double column_dot(const Matrix& X, Eigen::Index a, const Vector& v) {
  const Eigen::Index n = X.rows();
  return Eigen::Map<const Column<N>>(X.col(a).data(), n).dot(Eigen::Map<const Column<N>>(v.data(), n));
}

template <int N>
void transpose_multiply(const Matrix& X, const Vector& v, Vector& out) {
  out.resize(X.cols());
  for (Eigen::Index a = 0; a < X.cols(); ++a) out(a) = column_dot<N>(X, a, v);
}

template <int N>
void add_columns(const Matrix& G, const Vector& r, Vector& v) {
  const Eigen::Index n = G.rows();
  Eigen::Map<Column<N>> y(v.data(), n);
  for (Eigen::Index a = 0; a < G.cols(); ++a) y += r(a) * Eigen::Map<const Column<N>>(G.col(a).data(), n);
}

// f<N>(...) for N = n when n is one of the compiled sizes, else f<Eigen::Dynamic>.
template <class Kernel>
void dispatch(Eigen::Index n, Kernel&& kernel) {
  switch (n) {
    case 3: kernel(std::integral_constant<int, 3>{}); break;
    case 6: kernel(std::integral_constant<int, 6>{}); break;
    default: kernel(std::integral_constant<int, Eigen::Dynamic>{}); break;
  }
}

}  // namespace small_dense_detail

// out = A x (A square).
inline void small_multiply(const Matrix& A, const Vector& x, Vector& out) {
  small_dense_detail::dispatch(A.rows(), [&](auto N) { small_dense_detail::multiply<N()>(A, x, out); });
}

// G = A X, column a of G the combination of A's columns weighted by column a of X's nonzero entries
// (X = Hᵀ: a contact row has a handful).
inline void small_combine_columns(const Matrix& A, const Matrix& X, Matrix& G) {
  small_dense_detail::dispatch(A.rows(), [&](auto N) { small_dense_detail::combine_columns<N()>(A, X, G); });
}

// out = Xᵀ v (X = Hᵀ: the problem's rows applied to a velocity, a dense dot a row).
inline void small_transpose_multiply(const Matrix& X, const Vector& v, Vector& out) {
  small_dense_detail::dispatch(X.rows(), [&](auto N) { small_dense_detail::transpose_multiply<N()>(X, v, out); });
}

// Column a of X dotted with v: one entry of small_transpose_multiply's product, to the bit.
inline double small_column_dot(const Matrix& X, Eigen::Index a, const Vector& v) {
  double result = 0.0;
  small_dense_detail::dispatch(X.rows(), [&](auto N) { result = small_dense_detail::column_dot<N()>(X, a, v); });
  return result;
}

// v += Σ_a r_a G.col(a), column by column in a's order: each entry the same sum as the dynamic-size
// axpys', to the bit (no reassociation: an axpy is entry by entry).
inline void small_add_columns(const Matrix& G, const Vector& r, Vector& v) {
  small_dense_detail::dispatch(G.rows(), [&](auto N) { small_dense_detail::add_columns<N()>(G, r, v); });
}

// A diagonal matrix (a point's or an unsprung rigid body's mass, and then A⁻¹): its products go by its
// diagonal. Every other term of the full products is x·0 = ±0, which leaves a nonzero sum as it is and
// a zero one +0 (+0 + −0 = +0): from a +0 start, the sums are 0 + x_i d_i to the bit, as below.
inline bool is_diagonal(const Matrix& A) {
  for (Eigen::Index j = 0; j < A.cols(); ++j)
    for (Eigen::Index i = 0; i < A.rows(); ++i)
      if (i != j && A(i, j) != 0.0) return false;
  return true;
}

// out = D x, D = diag(diagonal): small_multiply's result for that D, to the bit.
inline void small_diagonal_multiply(const Vector& diagonal, const Vector& x, Vector& out) {
  out.resize(diagonal.size());
  for (Eigen::Index i = 0; i < diagonal.size(); ++i) out(i) = 0.0 + x(i) * diagonal(i);
}

// G = D X, D = diag(diagonal): small_combine_columns' result for that D, to the bit (it skips X's
// zero entries, whose column of D adds nothing; an entry then stays +0 = 0 + 0 · d_i).
inline void small_diagonal_columns(const Vector& diagonal, const Matrix& X, Matrix& G) {
  const Eigen::Index n = X.rows(), m = X.cols();
  G.resize(n, m);
  for (Eigen::Index a = 0; a < m; ++a)
    for (Eigen::Index i = 0; i < n; ++i) G(i, a) = 0.0 + X(i, a) * diagonal(i);
}

// W = Xᵀ G when it is known to be symmetric (the Delassus operator H A⁻¹ Hᵀ, X = Hᵀ, G = A⁻¹ Hᵀ):
// one triangle computed, mirrored.
inline void small_symmetric_gram(const Matrix& X, const Matrix& G, Matrix& W) {
  small_dense_detail::dispatch(X.rows(), [&](auto N) { small_dense_detail::symmetric_gram<N()>(X, G, W); });
}

}  // namespace csim
