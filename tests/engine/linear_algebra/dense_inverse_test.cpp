// The explicit inverse of a lumped World's iteration matrix, and the small products built on it.
#include "engine/linear_algebra/dense_inverse.h"
#include "engine/linear_algebra/small_dense_products.h"

#include <gtest/gtest.h>

#include <cstring>

#include <cmath>

namespace csim {
namespace {

Matrix spd(int n) {  // a mass-dominated, coupled symmetric positive definite matrix
  Matrix B = Matrix::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = std::sin(1.0 + i + 2.0 * j);
  Matrix A = B * B.transpose();
  A.diagonal().array() += n;
  return A;
}

TEST(DenseInverse, IsTheInverseAndExactlySymmetric) {
  for (int n : {1, 3, 6, 10}) {
    const Matrix A = spd(n);
    Matrix factor, inverse;
    ASSERT_TRUE(invert_positive_definite(A, factor, inverse)) << n;
    EXPECT_LT((A * inverse - Matrix::Identity(n, n)).cwiseAbs().maxCoeff(), 1e-13) << n;
    EXPECT_TRUE(inverse == inverse.transpose()) << n;
  }
}

TEST(DenseInverse, RefusesAMatrixThatIsNotPositiveDefinite) {
  Matrix A = spd(3);
  A(1, 1) = -A(1, 1);
  Matrix factor, inverse;
  EXPECT_FALSE(invert_positive_definite(A, factor, inverse));
}

// The fixed sizes (3, 6) and the dynamic one agree with Eigen's products.
TEST(SmallDenseProducts, AgreeWithEigensProducts) {
  for (int n : {2, 3, 6, 7}) {
    const Matrix A = spd(n);
    const Vector x = Vector::LinSpaced(n, -1.0, 2.0);
    Vector y;
    small_multiply(A, x, y);
    EXPECT_LT((y - A * x).cwiseAbs().maxCoeff(), 1e-13) << n;
    Matrix X = Matrix::Zero(n, 4);  // sparse columns, as the problem's rows
    X(0, 0) = 1.0;
    X(n - 1, 1) = -2.0;
    X(n / 2, 2) = 0.5;
    X(0, 3) = 3.0;
    X(n - 1, 3) = 1.0;
    Matrix G, W;
    small_combine_columns(A, X, G);
    EXPECT_LT((G - A * X).cwiseAbs().maxCoeff(), 1e-13) << n;
    small_symmetric_gram(X, G, W);
    EXPECT_LT((W - X.transpose() * A * X).cwiseAbs().maxCoeff(), 1e-12) << n;
    EXPECT_TRUE(W == W.transpose()) << n;
  }
}

// The rows applied to a velocity (Xᵀ v, and one entry of it) agree with Eigen's product, and
// small_column_dot is small_transpose_multiply's entry to the bit; v += G r column by column is the
// dynamic-size axpys' result to the bit (each entry the same sum in the same order).
TEST(SmallDenseProducts, RowsAppliedAndColumnsAddedAgreeWithEigens) {
  for (int n : {2, 3, 6, 7}) {
    const Matrix A = spd(n);
    const Matrix X = A.leftCols(std::min(n, 5));  // n × min(n, 5)
    const Vector v = Vector::LinSpaced(n, -1.5, 2.5);
    Vector Xt_v;
    small_transpose_multiply(X, v, Xt_v);
    ASSERT_EQ(Xt_v.size(), X.cols());
    EXPECT_LT((Xt_v - X.transpose() * v).cwiseAbs().maxCoeff(), 1e-13 * (X.transpose() * v).cwiseAbs().maxCoeff()) << n;
    for (Eigen::Index a = 0; a < X.cols(); ++a) EXPECT_EQ(small_column_dot(X, a, v), Xt_v(a)) << n << ", column " << a;
    const Vector r = Vector::LinSpaced(X.cols(), 0.3, -0.7);
    Vector summed = v, expected = v;
    small_add_columns(A.leftCols(X.cols()), r, summed);
    for (Eigen::Index a = 0; a < X.cols(); ++a) expected += r(a) * A.col(a);
    EXPECT_EQ(std::memcmp(summed.data(), expected.data(), n * sizeof(double)), 0) << n;
  }
}

// A diagonal matrix's products by its diagonal alone give the full products' results to the bit, the
// signs of their zeros included (the lumped step takes them for a point's or an unsprung body's M
// and A⁻¹); a matrix with one off-diagonal entry is not taken for diagonal.
TEST(SmallDenseProducts, DiagonalProductsAreTheFullOnesToTheBit) {
  const auto same_bits = [](const Matrix& a, const Matrix& b) {
    if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
    for (Eigen::Index i = 0; i < a.size(); ++i)
      if (!(a.data()[i] == b.data()[i] && std::signbit(a.data()[i]) == std::signbit(b.data()[i]))) return false;
    return true;
  };
  for (int n : {2, 3, 6, 7}) {
    Matrix D = Matrix::Zero(n, n);
    for (int i = 0; i < n; ++i) D(i, i) = 1.0 / (0.3 + i);
    D(n - 1, 0) = D(0, n - 1) = -0.0;  // a Cholesky inverse's zeros may be negative
    ASSERT_TRUE(is_diagonal(D)) << n;
    const Vector d = D.diagonal();
    Matrix X = Matrix::Zero(n, 5);  // sparse columns, as the problem's rows, with negative zeros
    for (int a = 0; a < 5; ++a)
      for (int j = 0; j < n; ++j)
        if ((a + j) % 3 != 0) X(j, a) = std::sin(1.0 + a + 3.0 * j);
    X(0, 1) = -0.0;
    X(n - 1, 2) = -1e-320;  // its product with d underflows
    Matrix G_full, G_diagonal;
    small_combine_columns(D, X, G_full);
    small_diagonal_columns(d, X, G_diagonal);
    EXPECT_TRUE(same_bits(G_full, G_diagonal)) << n;
    for (int a = 0; a < 5; ++a) {
      const Vector x = X.col(a);
      Vector y_full, y_diagonal;
      small_multiply(D, x, y_full);
      small_diagonal_multiply(d, x, y_diagonal);
      EXPECT_TRUE(same_bits(y_full, y_diagonal)) << n << ", column " << a;
    }
    D(1, 0) = 1e-300;
    EXPECT_FALSE(is_diagonal(D)) << n;
  }
}

// The Gram product with G's column kept in a local (n = 6) is the one that reads it through a map, to
// the bit: the same dot products of the same values.
TEST(SmallDenseProducts, SymmetricGramIsTheMappedOneToTheBit) {
  for (int n : {3, 6, 7}) {
    for (int m : {1, 4, 12}) {
      Matrix X(n, m), G(n, m);
      for (int j = 0; j < m; ++j)
        for (int i = 0; i < n; ++i) {
          X(i, j) = (i + j) % 4 == 0 ? -0.0 : std::sin(1.0 + 0.7 * i + 1.3 * j);
          G(i, j) = std::cos(0.2 + 1.9 * i - 0.4 * j) * std::pow(10.0, (i % 3) - 1);
        }
      Matrix expected(m, m), W;
      auto mapped = [&](auto size) {  // the former kernel: both columns read through maps of size N
        constexpr int N = decltype(size)::value;
        using Column = Eigen::Matrix<double, N, 1>;
        for (int b = 0; b < m; ++b)
          for (int a = 0; a <= b; ++a)
            expected(a, b) = expected(b, a) =
                Eigen::Map<const Column>(X.col(a).data(), n).dot(Eigen::Map<const Column>(G.col(b).data(), n));
      };
      if (n == 3) mapped(std::integral_constant<int, 3>{});
      else if (n == 6) mapped(std::integral_constant<int, 6>{});
      else mapped(std::integral_constant<int, Eigen::Dynamic>{});
      small_symmetric_gram(X, G, W);
      ASSERT_EQ(W.rows(), m);
      ASSERT_EQ(W.cols(), m);
      EXPECT_EQ(std::memcmp(W.data(), expected.data(), m * m * sizeof(double)), 0) << n << " x " << m;
    }
  }
}

}  // namespace
}  // namespace csim
