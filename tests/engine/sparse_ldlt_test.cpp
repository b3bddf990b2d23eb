// The sparse LDLᵀ of the Newton steppers (engine/sparse_ldlt.h): its Delassus operator from the forward
// substitution alone against H A⁻¹ Hᵀ from dense algebra, its positive-definiteness verdict, and the
// reuse of its symbolic analysis while the pattern stays.
#include "engine/sparse_ldlt.h"

#include <gtest/gtest.h>

namespace csim {
namespace {

// The stiffness of a chain of n unit springs held at one end: tridiagonal, positive definite; with
// `softened`, the spring at `where` negative (an indefinite tangent).
SparseMatrix chain(int n, double softened = 0.0, int where = -1) {
  Triplets t;
  for (int i = 0; i < n; ++i) {
    const double k = i == where ? softened : 1.0 + 0.1 * i;  // spring i joins node i − 1 (or the wall) to node i
    t.emplace_back(i, i, k);
    if (i > 0) {
      t.emplace_back(i - 1, i - 1, k);
      t.emplace_back(i - 1, i, -k);
      t.emplace_back(i, i - 1, -k);
    }
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

TEST(SparseLdlt, DelassusEqualsTheDenseProductOfContactRows) {
  const int n = 40;
  const SparseMatrix A = chain(n);
  SparseLdlt factor;
  ASSERT_TRUE(factor.factor_positive_definite(A));
  // Three contact rows with two or three entries each, one reaching the last node, and an empty row.
  Matrix H = Matrix::Zero(4, n);
  H(0, 3) = 1.0;
  H(0, 4) = -0.5;
  H(1, 20) = 0.3;
  H(1, 21) = 0.7;
  H(1, 39) = -1.0;
  H(2, 0) = 2.0;
  H(2, 10) = 1.0;
  Matrix W;
  factor.delassus(H, W);
  const Matrix expected = H * Matrix(A).ldlt().solve(H.transpose());
  EXPECT_LE((W - expected).lpNorm<Eigen::Infinity>(), 1e-12 * expected.lpNorm<Eigen::Infinity>());
  EXPECT_EQ(W.row(3).lpNorm<Eigen::Infinity>(), 0.0);  // a row with no entries couples to nothing
  const Vector b = Vector::LinSpaced(n, -1.0, 2.0);
  EXPECT_LE((factor.solve(b) - Matrix(A).ldlt().solve(b)).lpNorm<Eigen::Infinity>(), 1e-10);
}

TEST(SparseLdlt, DelassusOfManyLocalRowsEqualsTheDenseProduct) {
  // 60 rows on a 300-node chain, each on two neighbouring nodes: most rows of Y are reached by a few
  // columns (the direct products), those near the elimination tree's root by many (the matrix product).
  const int n = 300, m = 60;
  const SparseMatrix A = chain(n);
  SparseLdlt factor;
  ASSERT_TRUE(factor.factor_positive_definite(A));
  Matrix H = Matrix::Zero(m, n);
  for (int a = 0; a < m; ++a) {
    H(a, 5 * a) = 1.0;
    H(a, 5 * a + 1) = -0.3 - 0.01 * a;
  }
  Matrix W;
  factor.delassus(H, W);
  const Matrix expected = H * Matrix(A).ldlt().solve(H.transpose());
  EXPECT_LE((W - expected).lpNorm<Eigen::Infinity>(), 1e-12 * expected.lpNorm<Eigen::Infinity>());
  EXPECT_EQ((W - W.transpose()).lpNorm<Eigen::Infinity>(), 0.0);
}

TEST(SparseLdlt, ReportsAnIndefiniteMatrix) {
  SparseLdlt factor;
  EXPECT_FALSE(factor.factor_positive_definite(chain(10, -0.5, 4)));
  EXPECT_TRUE(factor.factor_positive_definite(chain(10)));
}

TEST(SparseLdlt, AnalysesThePatternOnlyWhenItChanges) {
  SparseLdlt factor;
  SparseMatrix A = chain(12);
  ASSERT_TRUE(factor.factor_positive_definite(A));
  ASSERT_TRUE(factor.factor_positive_definite(2.0 * A));  // new values, the same pattern
  EXPECT_EQ(factor.analyses(), 1);
  SparseMatrix coupled = A;
  coupled.coeffRef(0, 11) = -0.01;  // a new entry, left uncompressed by coeffRef
  coupled.coeffRef(11, 0) = -0.01;
  ASSERT_TRUE(factor.factor_positive_definite(coupled));
  EXPECT_EQ(factor.analyses(), 2);
  const Vector b = Vector::Ones(12);
  EXPECT_LE((factor.solve(b) - Matrix(coupled).ldlt().solve(b)).lpNorm<Eigen::Infinity>(), 1e-10);
}

}  // namespace
}  // namespace csim
