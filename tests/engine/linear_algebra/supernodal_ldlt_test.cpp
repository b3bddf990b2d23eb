// The supernodal numeric LDLᵀ (engine/linear_algebra/supernodal_ldlt.h): L D Lᵀ against the matrix it factors, on
// patterns with supernodes of every width (a grid of two-unknown nodes, a random sparse matrix whose
// elimination tree branches inside supernodes, an arrow matrix with dense last rows like a hub's);
// its verdict on matrices that are not positive definite; and, inside SparseLdlt, refactorizations of
// one pattern through CHOLMOD's storage that solve as a dense factorization does.
#include "engine/linear_algebra/sparse_ldlt.h"
#include "engine/linear_algebra/supernodal_ldlt.h"
#include "tests/engine/test_matrices.h"

#include <gtest/gtest.h>

#include <random>

namespace csim {
namespace {

using test::arrow;
using test::from_triplets;
using test::random_sparse;

// Factors A (its upper triangle, natural order) into a storage of L's own pattern; returns
// |L D Lᵀ − A|∞ / |A|∞ (NaN when the factorization reports a pivot that is not > 0).
double reconstruction_error(const SparseMatrix& A, int* supernodes = nullptr) {
  const test::SimplicialFactor f = test::simplicial_factor(A);
  if (supernodes) *supernodes = f.supernodes;
  EXPECT_TRUE(f.pattern_matches);
  if (!f.positive) return NAN;
  for (int j = 0; j < static_cast<int>(A.rows()); ++j) EXPECT_EQ(f.row[f.start[j]], j);  // the diagonal first
  const Matrix dense(A);
  return (f.L * f.D.asDiagonal() * f.L.transpose() - dense).lpNorm<Eigen::Infinity>() / dense.lpNorm<Eigen::Infinity>();
}

TEST(SupernodalLdlt, FactorsGridsRandomAndArrowPatterns) {
  std::mt19937 random(11);
  int supernodes = 0;
  EXPECT_LE(reconstruction_error(test::random_grid(9, random), &supernodes), 1e-14);
  EXPECT_LT(supernodes, 162);  // a node's two unknowns share a supernode
  for (int trial = 0; trial < 5; ++trial) EXPECT_LE(reconstruction_error(random_sparse(120, random)), 1e-14);
  EXPECT_LE(reconstruction_error(arrow(60, 3), &supernodes), 1e-14);
  EXPECT_LE(reconstruction_error(from_triplets(1, {{0, 0, 2.0}})), 1e-15);
  Triplets diagonal;
  for (int i = 0; i < 7; ++i) diagonal.emplace_back(i, i, 1.0 + i);
  EXPECT_EQ(reconstruction_error(from_triplets(7, diagonal)), 0.0);
}

TEST(SupernodalLdlt, ReportsAPivotThatIsNotPositive) {
  std::mt19937 random(3);
  SparseMatrix A = test::random_grid(5, random);
  EXPECT_TRUE(std::isnan(reconstruction_error(-1.0 * A)));
  A.coeffRef(17, 17) = -50.0;  // one unknown's own stiffness negative: indefinite
  EXPECT_TRUE(std::isnan(reconstruction_error(A)));
}

TEST(SupernodalLdlt, RefactorizationsInSparseLdltSolveAsTheDenseFactorization) {
  std::mt19937 random(5);
  SparseMatrix A = random_sparse(150, random);
  const int n = static_cast<int>(A.rows());
  const Vector b = Vector::LinSpaced(n, -1.0, 2.0);
  SparseLdlt factor;
  ASSERT_TRUE(factor.factor_positive_definite(A));
  EXPECT_EQ(factor.supernodal_factorizations(), 0);  // a pattern's first factorization is CHOLMOD's
  for (int pass = 0; pass < 3; ++pass) {
    for (int p = 0; p < A.nonZeros(); ++p) A.valuePtr()[p] *= 1.0 + 0.2 * std::sin(3.0 * p + pass);
    A = 0.5 * (A + SparseMatrix(A.transpose()));
    A.diagonal().array() += 2.0 * n;  // stays positive definite
    ASSERT_TRUE(factor.factor_positive_definite(A));
    EXPECT_EQ(factor.supernodal_factorizations(), pass + 1);
    const Vector expected = Matrix(A).ldlt().solve(b);
    EXPECT_LE((factor.solve(b) - expected).lpNorm<Eigen::Infinity>(), 1e-13 * expected.lpNorm<Eigen::Infinity>());
    // The forward columns read the new factor: a diagonal entry of A⁻¹.
    const int index[] = {pass * 7};
    const double value[] = {1.0};
    SparseLdlt::ForwardColumn y;
    factor.forward(index, value, 1, y);
    const double inverse = Matrix(A).ldlt().solve(Vector::Unit(n, index[0]))(index[0]);
    EXPECT_NEAR(factor.delassus_entry(y, y), inverse, 1e-13 * inverse);
  }
  // Not positive definite: refused, and the factor left is CHOLMOD's complete LDLᵀ, as before; the
  // next positive definite matrix is supernodal again.
  EXPECT_FALSE(factor.factor_positive_definite(-1.0 * A));
  EXPECT_EQ(factor.supernodal_factorizations(), 4);
  ASSERT_TRUE(factor.factor_positive_definite(A));
  EXPECT_EQ(factor.supernodal_factorizations(), 5);
  EXPECT_EQ(factor.analyses(), 1);
  const Vector expected = Matrix(A).ldlt().solve(b);
  EXPECT_LE((factor.solve(b) - expected).lpNorm<Eigen::Infinity>(), 1e-13 * expected.lpNorm<Eigen::Infinity>());
}

}  // namespace
}  // namespace csim
