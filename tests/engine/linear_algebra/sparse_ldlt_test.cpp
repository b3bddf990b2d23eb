// The sparse LDLᵀ of the steppers (engine/linear_algebra/sparse_ldlt.h, on CHOLMOD): its Delassus operator from the
// forward substitution alone against H A⁻¹ Hᵀ from dense algebra, its sparse forward columns, its
// positive-definiteness verdict, the reuse of its symbolic analysis while the pattern stays, and the
// Delassus operator it keeps while neither the factor nor the rows change.
#include "engine/linear_algebra/sparse_ldlt.h"
#include "tests/engine/test_matrices.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>

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

TEST(SparseLdlt, ForwardColumnsGiveTheDelassusOperatorOfARandomSparseMatrix) {
  std::mt19937 random(31);
  const SparseMatrix A = test::random_grid(12, random);
  const int n = static_cast<int>(A.rows()), m = 9;
  SparseLdlt factor;
  ASSERT_TRUE(factor.factor_positive_definite(A));
  std::uniform_int_distribution<int> unknown(0, n - 1);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Matrix H = Matrix::Zero(m, n);
  std::vector<SparseLdlt::ForwardColumn> y(m);
  for (int a = 0; a < m; ++a) {
    std::vector<int> index;
    std::vector<double> value;
    for (int k = 0; k < 1 + a % 4; ++k) {
      const int j = unknown(random);
      if (H(a, j) != 0.0) continue;
      H(a, j) = uniform(random);
      index.push_back(j);
      value.push_back(H(a, j));
    }
    factor.forward(index.data(), value.data(), static_cast<int>(index.size()), y[a]);
    EXPECT_LT(static_cast<int>(y[a].index.size()), n);  // the reach, not all of L
    EXPECT_TRUE(std::is_sorted(y[a].index.begin(), y[a].index.end()));
  }
  const Matrix expected = H * Matrix(A).ldlt().solve(H.transpose());
  const double scale = expected.lpNorm<Eigen::Infinity>();
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) {
      EXPECT_NEAR(factor.delassus_entry(y[a], y[b]), expected(a, b), 1e-12 * scale) << a << ", " << b;
      EXPECT_EQ(factor.delassus_entry(y[a], y[b]), factor.delassus_entry(y[b], y[a]));
    }
  Matrix W;
  factor.delassus(H, W);
  EXPECT_LE((W - expected).lpNorm<Eigen::Infinity>(), 1e-12 * scale);
  // A forward column is the forward substitution alone: Yᵀ D⁻¹ Y of one row against hᵀ A⁻¹ h.
  Vector x = Vector::Zero(n);
  factor.scatter_scaled(y[3], x);
  EXPECT_NEAR(SparseLdlt::dot(y[5], x), expected(5, 3), 1e-12 * scale);
  EXPECT_GE(factor.factor_nonzeros(), A.nonZeros() / 2);
  // A⁻¹ Hᵀ r from Y r and a backward substitution.
  const Vector r = Vector::LinSpaced(m, 0.5, -1.5);
  Vector z = Vector::Zero(n), v;
  for (int a = 0; a < m; ++a)
    for (std::size_t k = 0; k < y[a].index.size(); ++k) z(y[a].index[k]) += r(a) * y[a].value[k];
  factor.back_substitute(z, v);
  const Vector expected_v = Matrix(A).ldlt().solve(H.transpose() * r);
  EXPECT_LE((v - expected_v).lpNorm<Eigen::Infinity>(), 1e-11 * expected_v.lpNorm<Eigen::Infinity>());
  // A solve in two halves (moreau_jean.h): w = L⁻¹ P f and D⁻¹ w give each row's H A⁻¹ f by its forward
  // column, and A⁻¹ (f + Hᵀ r) is the backward half of w + Y r.
  const Vector f = Vector::LinSpaced(n, -2.0, 3.0);
  Vector w, scaled;
  factor.forward_substitute(f, w, scaled);
  const Vector expected_free = Matrix(A).ldlt().solve(f);
  const Vector rows_free = H * expected_free;
  for (int a = 0; a < m; ++a)
    EXPECT_NEAR(SparseLdlt::dot(y[a], scaled), rows_free(a), 1e-12 * rows_free.lpNorm<Eigen::Infinity>()) << a;
  z += w;
  factor.back_substitute(z, v);
  const Vector expected_total = expected_free + expected_v;
  EXPECT_LE((v - expected_total).lpNorm<Eigen::Infinity>(), 1e-11 * expected_total.lpNorm<Eigen::Infinity>());
}

// Whether two matrices hold the same numbers to the bit.
bool same_bits(const Matrix& a, const Matrix& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

TEST(SparseLdlt, KeepsTheInverseBlockWhileTheFactorAndTheUnknownsStayTheSame) {
  std::mt19937 random(5);
  const SparseMatrix A = test::random_grid(8, random);
  const int n = static_cast<int>(A.rows()), m = 6;
  std::uniform_int_distribution<int> unknown(0, n - 1);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Matrix H = Matrix::Zero(m, n);
  for (int a = 0; a < m; ++a)
    for (int k = 0; k < 3; ++k) H(a, unknown(random)) = uniform(random);
  SparseLdlt factor, fresh;
  ASSERT_TRUE(factor.factor_positive_definite(A));
  Matrix first, kept, recomputed;
  factor.delassus(H, first);
  factor.delassus(H, kept);
  EXPECT_EQ(factor.kept_delassus(), 1);
  ASSERT_TRUE(fresh.factor_positive_definite(A));
  fresh.delassus(H, recomputed);
  EXPECT_TRUE(same_bits(kept, recomputed));
  EXPECT_TRUE(same_bits(kept, first));
  // W from the kept G is W from a G of its own, to the bit; `kept` says whether G was kept. The other
  // factor is made the same way as factor's (a refactorization of a pattern is supernodal: `before`).
  const auto expect_fresh = [&](const SparseMatrix& matrix, const Matrix& rows, long kept_so_far,
                                const SparseMatrix* before = nullptr) {
    SparseLdlt other;
    if (before) {
      ASSERT_TRUE(other.factor_positive_definite(*before));
    }
    ASSERT_TRUE(other.factor_positive_definite(matrix));
    Matrix expected, W;
    other.delassus(rows, expected);
    factor.delassus(rows, W);
    EXPECT_TRUE(same_bits(W, expected));
    EXPECT_LE((W - rows * Matrix(matrix).ldlt().solve(rows.transpose())).lpNorm<Eigen::Infinity>(),
              1e-12 * expected.lpNorm<Eigen::Infinity>());
    EXPECT_EQ(factor.kept_delassus(), kept_so_far);
  };
  int row = 2, column = 0;
  while (H(row, column) == 0.0) ++column;
  // Values changed on the same unknowns (a turned row): G kept.
  Matrix changed = H;
  changed(row, column) = std::nextafter(H(row, column), 2.0);
  expect_fresh(A, changed, 2);
  expect_fresh(A, 0.5 * H, 3);
  // An entry moved to an unknown no row touched, a row fewer that leaves one untouched, another
  // factor: G of its own.
  int free_column = 0;
  while (H.col(free_column).cwiseAbs().maxCoeff() > 0.0) ++free_column;
  Matrix moved = H;
  moved(row, column) = 0.0;
  moved(row, free_column) = H(row, column);
  expect_fresh(A, moved, 3);
  expect_fresh(A, H, 3);
  Matrix fewer = H;
  fewer.row(row).setZero();
  const bool leaves_one = (H.colwise().squaredNorm().array() > 0.0).count() !=
                          (fewer.colwise().squaredNorm().array() > 0.0).count();
  ASSERT_TRUE(leaves_one);
  expect_fresh(A, fewer, 3);
  expect_fresh(A, H, 3);
  const SparseMatrix stiffer = 2.0 * A;
  ASSERT_TRUE(factor.factor_positive_definite(stiffer));
  expect_fresh(stiffer, H, 3, &A);
}

TEST(SparseLdlt, SolvesAroundAContactSolveWithTheRowsInverseBlock) {
  std::mt19937 random(7);
  const SparseMatrix A = test::random_grid(9, random);
  const int n = static_cast<int>(A.rows()), m = 5;
  std::uniform_int_distribution<int> unknown(0, n - 1);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Matrix H = Matrix::Zero(m, n);
  for (int a = 0; a < m; ++a)
    for (int k = 0; k < 3; ++k) H(a, unknown(random)) = uniform(random);
  const Vector f = Vector::LinSpaced(n, -2.0, 1.0), r = Vector::LinSpaced(m, 0.5, -1.5);
  const Eigen::LDLT<Matrix> dense(A);
  SparseLdlt factor;
  ASSERT_TRUE(factor.factor_positive_definite(A));
  Vector Hx, x;
  EXPECT_THROW(factor.solve_free(f, Hx), std::logic_error);  // no inverse block for this factor yet
  Matrix W;
  factor.delassus(H, W);
  factor.solve_free(f, Hx);
  const Vector free = dense.solve(f);
  EXPECT_LE((Hx - H * free).lpNorm<Eigen::Infinity>(), 1e-12 * (H * free).lpNorm<Eigen::Infinity>());
  factor.solve_with_reactions(r, x);
  const Vector expected = dense.solve(f + H.transpose() * r);
  EXPECT_LE((x - expected).lpNorm<Eigen::Infinity>(), 1e-12 * expected.lpNorm<Eigen::Infinity>());
  // With the block kept (the same unknowns, turned rows): the same halves.
  const Matrix turned = 1.5 * H;
  factor.delassus(turned, W);
  EXPECT_EQ(factor.kept_delassus(), 1);
  factor.solve_free(f, Hx);
  EXPECT_LE((Hx - turned * free).lpNorm<Eigen::Infinity>(), 1e-12 * (turned * free).lpNorm<Eigen::Infinity>());
  factor.solve_with_reactions(r, x);
  const Vector turned_expected = dense.solve(f + turned.transpose() * r);
  EXPECT_LE((x - turned_expected).lpNorm<Eigen::Infinity>(), 1e-12 * turned_expected.lpNorm<Eigen::Infinity>());
  ASSERT_TRUE(factor.factor_positive_definite(2.0 * A));
  EXPECT_THROW(factor.solve_free(f, Hx), std::logic_error);  // the block is the last factor's
}

// A factor whose pattern map was released (a constant A, factored once) solves and gives forward
// columns as before, to the bit; a later factorization analyses the pattern again and gives the same factor.
TEST(SparseLdlt, ReleasedPatternKeepsTheFactorAndIsAnalysedAgain) {
  std::mt19937 random(11);
  const SparseMatrix A = test::random_grid(6, random);
  SparseLdlt factor;
  ASSERT_TRUE(factor.factor_positive_definite(A));
  const Vector b = Vector::LinSpaced(A.rows(), -1.0, 3.0);
  const int index[] = {3, 7};
  const double value[] = {1.0, -0.5};
  SparseLdlt::ForwardColumn before, after;
  const Vector x = factor.solve(b);
  factor.forward(index, value, 2, before);
  factor.release_pattern();
  EXPECT_TRUE(factor.solve(b) == x);
  factor.forward(index, value, 2, after);
  EXPECT_EQ(after.index, before.index);
  EXPECT_EQ(after.value, before.value);
  ASSERT_TRUE(factor.factor_positive_definite(A));
  EXPECT_EQ(factor.analyses(), 2);
  EXPECT_TRUE(factor.solve(b) == x);
}

TEST(SparseLdlt, SolvesLikeADenseFactorizationAfterARefactorization) {
  std::mt19937 random(7);
  SparseMatrix A = test::random_grid(6, random);
  SparseLdlt factor;
  ASSERT_TRUE(factor.factor_positive_definite(A));
  const Vector b = Vector::LinSpaced(A.rows(), 1.0, -2.0);
  EXPECT_LE((factor.solve(b) - Matrix(A).ldlt().solve(b)).lpNorm<Eigen::Infinity>(), 1e-9);
  A *= 3.0;
  A.diagonal().array() += 0.5;
  ASSERT_TRUE(factor.factor_positive_definite(A));
  EXPECT_EQ(factor.analyses(), 1);
  EXPECT_EQ(factor.factorizations(), 2);
  Vector x = b;
  factor.solve_in_place(x);
  EXPECT_LE((x - Matrix(A).ldlt().solve(b)).lpNorm<Eigen::Infinity>(), 1e-9);
  // A forward column after the refactorization is the new factor's.
  const int index[] = {5};
  const double value[] = {1.0};
  SparseLdlt::ForwardColumn y;
  factor.forward(index, value, 1, y);
  EXPECT_NEAR(factor.delassus_entry(y, y), Matrix(A).ldlt().solve(Vector::Unit(A.rows(), 5))(5), 1e-12);
}

TEST(SparseLdlt, ReportsNegativeDefiniteAndSingularMatricesAndRecovers) {
  SparseLdlt factor;
  const SparseMatrix A = chain(6);
  EXPECT_FALSE(factor.factor_positive_definite(-1.0 * A));  // every pivot negative
  EXPECT_FALSE(factor.factor_positive_definite(chain(6, 0.0, 0)));  // no wall spring: singular
  EXPECT_TRUE(factor.factor_positive_definite(A));
  EXPECT_EQ(factor.analyses(), 1);
}

}  // namespace
}  // namespace csim

namespace csim {
namespace {

// small_pivots (sparse_ldlt.h): the chain held at its wall by a spring of k0 instead of 1. A spring at
// round-off of the others (1e-14, of either sign, or 0) is found whatever the scale of the matrix, and
// only that direction; a soft but real one (1e-6) is not.
TEST(SparseLdlt, SmallPivotsFindADirectionHeldAtRoundOffWhateverTheScale) {
  const int n = 30;
  for (double k0 : {1e-14, -1e-14, 0.0, 1e-6}) {
    for (double scale : {1e-8, 1.0, 2e11}) {
      SparseMatrix A = chain(n);
      A.coeffRef(0, 0) += k0 - 1.0;  // spring 0 (node 0 to the wall) of k0
      A *= scale;
      SparseLdlt factor;
      factor.factor_positive_definite(A);
      const Vector diagonal = A.diagonal();
      const std::vector<int> small = factor.small_pivots(diagonal, 1e-10);
      if (k0 == 1e-6) {
        EXPECT_TRUE(small.empty()) << "k0 " << k0 << ", scale " << scale;
        continue;
      }
      ASSERT_EQ(small.size(), 1u) << "k0 " << k0 << ", scale " << scale;
      // The direction (the whole chain's translation) held again at that unknown: no small pivot left.
      A.coeffRef(small[0], small[0]) += 1e-6 * diagonal(small[0]);
      factor.factor_positive_definite(A);
      EXPECT_TRUE(factor.small_pivots(A.diagonal(), 1e-10).empty()) << "k0 " << k0 << ", scale " << scale;
    }
  }
}

}  // namespace
}  // namespace csim

namespace csim {
namespace {

// What the steppers read of a factor, for rows H: W from the forward columns and from delassus, H A⁻¹ f
// and A⁻¹ (f + Hᵀ r) from the two halves (forward_substitute, back_substitute) and from solve_free and
// solve_with_reactions, and a whole solve.
struct FactorReadings {
  Matrix W_columns, W;
  Vector rows_free, total, Hx, x, solved;
};

FactorReadings readings(SparseLdlt& factor, const Matrix& H, const Vector& f, const Vector& r) {
  const int m = static_cast<int>(H.rows()), n = static_cast<int>(H.cols());
  FactorReadings out;
  std::vector<SparseLdlt::ForwardColumn> y(m);
  for (int a = 0; a < m; ++a) {
    std::vector<int> index;
    std::vector<double> value;
    for (int j = 0; j < n; ++j)
      if (H(a, j) != 0.0) {
        index.push_back(j);
        value.push_back(H(a, j));
      }
    factor.forward(index.data(), value.data(), static_cast<int>(index.size()), y[a]);
    EXPECT_TRUE(std::is_sorted(y[a].index.begin(), y[a].index.end()));
    EXPECT_LT(static_cast<int>(y[a].index.size()), n);  // the reach, not all of L
  }
  out.W_columns.resize(m, m);
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) out.W_columns(a, b) = factor.delassus_entry(y[a], y[b]);
  Vector w, z;
  factor.forward_substitute(f, w, z);
  out.rows_free.resize(m);
  for (int a = 0; a < m; ++a) out.rows_free(a) = SparseLdlt::dot(y[a], z);
  for (int a = 0; a < m; ++a) SparseLdlt::add_scaled(r(a), y[a], w);
  factor.back_substitute(w, out.total);
  factor.delassus(H, out.W);
  factor.solve_free(f, out.Hx);
  factor.solve_with_reactions(r, out.x);
  out.solved = factor.solve(f);
  return out;
}

// The fallback to CHOLMOD's routines (sparse_ldlt.h, cholmod_layout_supported): a factor our kernels do
// not read, CHOLMOD's simplicial LDLᵀ by choice (Kernels::cholmod) or that factor turned into LLᵀ by
// CHOLMOD, whose layout the check refuses (Kernels::cholmod_ll), gives what our kernels give, and what dense algebra
// gives, on a random grid's matrix of 800 unknowns: after CHOLMOD's factorization and after a
// refactorization of the same pattern (supernodal_ldlt.h for our kernels, CHOLMOD's for the fallback).
TEST(SparseLdlt, CholmodsRoutinesGiveWhatOurKernelsGiveWhereTheLayoutIsNotOurs) {
  std::mt19937 random(17);
  SparseMatrix A = test::random_grid(20, random);
  const int n = static_cast<int>(A.rows()), m = 12;
  std::uniform_int_distribution<int> unknown(0, n - 1);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Matrix H = Matrix::Zero(m, n);
  for (int a = 0; a < m; ++a)
    for (int k = 0; k < 1 + a % 3; ++k) H(a, unknown(random)) = uniform(random);
  const Vector f = Vector::LinSpaced(n, -2.0, 3.0), r = Vector::LinSpaced(m, 0.5, -1.5);
  SparseLdlt ours, cholmod(SparseLdlt::Kernels::cholmod), ll(SparseLdlt::Kernels::cholmod_ll);
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1)  // the same pattern, other values (still positive definite): a refactorization
      for (int j = 0; j < n; ++j) A.coeffRef(j, j) *= 1.0 + 0.3 * (j % 3);
    ASSERT_TRUE(ours.factor_positive_definite(A));
    EXPECT_TRUE(ours.reads_factor_storage());
    EXPECT_EQ(ours.supernodal_factorizations(), pass);
    const FactorReadings expected = readings(ours, H, f, r);
    // Dense algebra, independently.
    const Eigen::LDLT<Matrix> dense{Matrix(A)};
    const Matrix W = H * dense.solve(H.transpose());
    const Vector free = dense.solve(f), total = dense.solve(f + H.transpose() * r);
    const double w_scale = W.lpNorm<Eigen::Infinity>(), free_scale = (H * free).lpNorm<Eigen::Infinity>();
    const double x_scale = total.lpNorm<Eigen::Infinity>();
    EXPECT_LE((expected.W - W).lpNorm<Eigen::Infinity>(), 1e-12 * w_scale);
    EXPECT_LE((expected.total - total).lpNorm<Eigen::Infinity>(), 1e-11 * x_scale);
    for (SparseLdlt* fallback : {&cholmod, &ll}) {
      ASSERT_TRUE(fallback->factor_positive_definite(A));
      EXPECT_FALSE(fallback->reads_factor_storage());
      EXPECT_EQ(fallback->supernodal_factorizations(), 0);
      const FactorReadings got = readings(*fallback, H, f, r);
      EXPECT_LE((got.W_columns - expected.W_columns).lpNorm<Eigen::Infinity>(), 1e-12 * w_scale) << pass;
      EXPECT_LE((got.W - expected.W).lpNorm<Eigen::Infinity>(), 1e-12 * w_scale) << pass;
      EXPECT_LE((got.rows_free - expected.rows_free).lpNorm<Eigen::Infinity>(), 1e-12 * free_scale) << pass;
      EXPECT_LE((got.Hx - expected.Hx).lpNorm<Eigen::Infinity>(), 1e-12 * free_scale) << pass;
      EXPECT_LE((got.total - expected.total).lpNorm<Eigen::Infinity>(), 1e-11 * x_scale) << pass;
      EXPECT_LE((got.x - expected.x).lpNorm<Eigen::Infinity>(), 1e-11 * x_scale) << pass;
      EXPECT_LE((got.solved - expected.solved).lpNorm<Eigen::Infinity>(), 1e-11 * free.lpNorm<Eigen::Infinity>()) << pass;
      EXPECT_EQ(fallback->factor_nonzeros(), ours.factor_nonzeros());
    }
    // CHOLMOD's LDLᵀ forward columns are ours: the same rows (the reach), the same values.
    for (int j : {0, n / 2, n - 1}) {
      const double one = 1.0;
      SparseLdlt::ForwardColumn a, b;
      ours.forward(&j, &one, 1, a);
      cholmod.forward(&j, &one, 1, b);
      ASSERT_EQ(a.index, b.index) << j;
      for (std::size_t k = 0; k < a.value.size(); ++k) EXPECT_NEAR(a.value[k], b.value[k], 1e-13) << j;
    }
  }
}

// The verdicts that read D go through CHOLMOD alike: positive definiteness and small pivots.
TEST(SparseLdlt, CholmodsRoutinesGiveTheSameVerdictsOnDefinitenessAndSmallPivots) {
  for (const SparseLdlt::Kernels kernels : {SparseLdlt::Kernels::ours_where_supported, SparseLdlt::Kernels::cholmod,
                                            SparseLdlt::Kernels::cholmod_ll}) {
    const int label = static_cast<int>(kernels);
    SparseLdlt factor(kernels);
    EXPECT_FALSE(factor.factor_positive_definite(-1.0 * chain(6))) << label;
    EXPECT_FALSE(factor.factor_positive_definite(chain(6, 0.0, 0))) << label;
    EXPECT_FALSE(factor.factor_positive_definite(chain(6, -0.5, 3))) << label;  // one negative spring
    EXPECT_TRUE(factor.factor_positive_definite(chain(6))) << label;
    SparseMatrix A = chain(30);
    A.coeffRef(0, 0) += 1e-14 - 1.0;  // the wall spring at round-off of the others
    A *= 2e11;
    EXPECT_TRUE(factor.factor_positive_definite(A)) << label;
    const std::vector<int> small = factor.small_pivots(A.diagonal(), 1e-10);
    ASSERT_EQ(small.size(), 1u) << label;
    A.coeffRef(small[0], small[0]) += 1e-6 * A.coeff(small[0], small[0]);
    EXPECT_TRUE(factor.factor_positive_definite(A)) << label;
    EXPECT_TRUE(factor.small_pivots(A.diagonal(), 1e-10).empty()) << label;
  }
}

}  // namespace
}  // namespace csim
