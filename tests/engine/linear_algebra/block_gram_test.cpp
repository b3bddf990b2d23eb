// The sparse Delassus operator by whole blocks (engine/linear_algebra/block_gram.h) against H A⁻¹ Hᵀ
// from dense algebra, on an iteration matrix that couples some bodies and not others: the entries (3D
// and 2D contacts' blocks, equality rows' 1-wide ones), the exact symmetry, a pattern that holds exactly
// the blocks of rows moving a common body, the work space kept from a larger problem, and the refusal of
// a W too dense.
#include "engine/linear_algebra/block_gram.h"

#include <gtest/gtest.h>

#include <array>
#include <random>

namespace csim {
namespace {

constexpr int kBody = 6;  // unknowns of a body (a rigid body in space)

// Five bodies, each a random positive definite 6 × 6 block; bodies 3 and 4 joined by a spring on one
// unknown (A then couples them), the others apart.
SparseMatrix iteration_matrix() {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Matrix A = Matrix::Zero(5 * kBody, 5 * kBody);
  for (int body = 0; body < 5; ++body) {
    Matrix B(kBody, kBody);
    for (int i = 0; i < kBody; ++i)
      for (int j = 0; j < kBody; ++j) B(i, j) = uniform(random);
    A.block(body * kBody, body * kBody, kBody, kBody) = B * B.transpose() + kBody * Matrix::Identity(kBody, kBody);
  }
  const int i = 3 * kBody, j = 4 * kBody + 2;
  A(i, i) += 50.0;
  A(j, j) += 50.0;
  A(i, j) -= 50.0;
  A(j, i) -= 50.0;
  return A.sparseView();
}

// The forward columns of H's rows, and pointers to them.
struct Columns {
  std::vector<SparseLdlt::ForwardColumn> forward;
  std::vector<const SparseLdlt::ForwardColumn*> pointers;
};

Columns forward_columns(const SparseLdlt& factor, const Matrix& H) {
  Columns columns;
  columns.forward.resize(H.rows());
  for (int a = 0; a < H.rows(); ++a) {
    std::vector<int> index;
    std::vector<double> value;
    for (int j = 0; j < H.cols(); ++j)
      if (H(a, j) != 0.0) {
        index.push_back(j);
        value.push_back(H(a, j));
      }
    factor.forward(index.data(), value.data(), static_cast<int>(index.size()), columns.forward[a]);
  }
  for (const SparseLdlt::ForwardColumn& y : columns.forward) columns.pointers.push_back(&y);
  return columns;
}

// Rows of `dimension` random entries on each body of each contact (−1: none), then one equality row on
// each listed unknown (a unit row).
Matrix contact_rows(const std::vector<std::array<int, 2>>& contact_bodies, int dimension,
                    const std::vector<int>& equality_unknowns, int unknowns, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const int contacts = static_cast<int>(contact_bodies.size());
  Matrix H = Matrix::Zero(dimension * contacts + static_cast<int>(equality_unknowns.size()), unknowns);
  for (int c = 0; c < contacts; ++c)
    for (int k = 0; k < dimension; ++k)
      for (const int body : contact_bodies[c])
        if (body >= 0)
          for (int u = 0; u < kBody; ++u) H(dimension * c + k, body * kBody + u) = uniform(random);
  for (std::size_t e = 0; e < equality_unknowns.size(); ++e) H(dimension * contacts + e, equality_unknowns[e]) = 1.0;
  return H;
}

TEST(BlockGram, EqualsTheDenseDelassusWithTheBlocksOfRowsSharingABody) {
  const SparseMatrix A = iteration_matrix();
  SparseLdlt factor;
  ASSERT_TRUE(factor.factor_positive_definite(A));
  // Four contacts in 3D (three rows each) between bodies (0, 1), (1, 2), (3, -), (2, -), then one
  // equality row on body 4: a contact row has entries on each of its bodies' six unknowns.
  const int contact_bodies[4][2] = {{0, 1}, {1, 2}, {3, -1}, {2, -1}};
  const int contacts = 4, m = 3 * contacts + 1;
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Matrix H = Matrix::Zero(m, A.cols());
  for (int c = 0; c < contacts; ++c)
    for (int k = 0; k < 3; ++k)
      for (const int body : contact_bodies[c])
        if (body >= 0)
          for (int u = 0; u < kBody; ++u) H(3 * c + k, body * kBody + u) = uniform(random);
  H(m - 1, 4 * kBody + 1) = 1.0;

  const Columns columns = forward_columns(factor, H);
  Eigen::SparseMatrix<double, Eigen::RowMajor> W;
  BlockGram gram;
  ASSERT_TRUE(gram.assemble(factor, columns.pointers, 3, contacts, W));

  const Matrix expected = H * Matrix(A).ldlt().solve(H.transpose());
  const Matrix dense = Matrix(W);
  EXPECT_LE((dense - expected).lpNorm<Eigen::Infinity>(), 1e-12 * expected.lpNorm<Eigen::Infinity>());
  EXPECT_TRUE(dense == dense.transpose());

  // The pattern: block (p, q) stored whole exactly when the two rows' bodies share one, or are joined
  // through A (bodies 3 and 4: contact 2 and the equality).
  auto bodies_of = [&](int block) -> std::vector<int> {
    if (block == contacts) return {4};
    std::vector<int> list;
    for (const int body : contact_bodies[block])
      if (body >= 0) list.push_back(body == 4 ? 3 : body);  // 3 and 4 are one component of A
    return list;
  };
  auto couples = [&](int p, int q) {
    for (const int x : bodies_of(p))
      for (const int y : bodies_of(q))
        if (x == y || (x == 4 && y == 3) || (x == 3 && y == 4)) return true;
    return false;
  };
  auto block_of = [&](int a) { return a < 3 * contacts ? a / 3 : contacts; };
  long stored = 0;
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) {
      bool present = false;
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(W, a); it; ++it)
        present = present || it.col() == b;
      const bool coupled = couples(block_of(a), block_of(b)) || couples(block_of(b), block_of(a));
      EXPECT_EQ(present, coupled) << "entry (" << a << ", " << b << ")";
      stored += present;
    }
  EXPECT_EQ(stored, W.nonZeros());
  EXPECT_LT(W.nonZeros(), m * m);  // contacts 0 and 2 share nothing
}

// 2D contacts (two rows each: blocks of 2 × 2) and three equality rows (1-wide blocks: with each other,
// with contacts, and one on a body no contact moves), assembled after a larger problem by the same
// BlockGram (its work space then longer than this problem's lists).
TEST(BlockGram, TwoDimensionalBlocksAndEqualityRowsEqualTheDenseDelassus) {
  const SparseMatrix A = iteration_matrix();
  SparseLdlt factor;
  ASSERT_TRUE(factor.factor_positive_definite(A));
  BlockGram gram;
  Eigen::SparseMatrix<double, Eigen::RowMajor> W;
  const Matrix larger = contact_rows({{0, 1}, {1, 2}, {2, 3}, {3, 4}, {0, 4}, {1, -1}, {2, -1}}, 3, {1, 20}, A.cols(), 5);
  const Columns larger_columns = forward_columns(factor, larger);
  ASSERT_TRUE(gram.assemble(factor, larger_columns.pointers, 3, 7, W));

  // Contacts (0, 1), (1, -), (3, -), (0, -); equalities on unknowns of bodies 0, 2 (no contact) and 4
  // (coupled to 3 through A).
  const Matrix H = contact_rows({{0, 1}, {1, -1}, {3, -1}, {0, -1}}, 2, {3, 2 * kBody + 1, 4 * kBody + 5}, A.cols(), 13);
  const Columns columns = forward_columns(factor, H);
  ASSERT_TRUE(gram.assemble(factor, columns.pointers, 2, 4, W));
  ASSERT_EQ(W.rows(), H.rows());
  ASSERT_EQ(W.cols(), H.rows());
  const Matrix expected = H * Matrix(A).ldlt().solve(H.transpose());
  const Matrix dense = Matrix(W);
  EXPECT_LE((dense - expected).lpNorm<Eigen::Infinity>(), 1e-12 * expected.lpNorm<Eigen::Infinity>());
  EXPECT_TRUE(dense == dense.transpose());
  // Zero blocks are not stored: contact 1 (body 1) and contact 2 (body 3) share nothing, nor do the
  // equality on body 2 and any contact; the equality on body 0 and contact 0 share body 0.
  for (int a = 0; a < W.rows(); ++a)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(W, a); it; ++it) {
      const int b = static_cast<int>(it.col());
      EXPECT_FALSE((a / 2 == 1 && b / 2 == 2 && b < 8) || (a / 2 == 2 && b / 2 == 1 && a < 8)) << a << ", " << b;
      EXPECT_FALSE((a == 9 && b < 8) || (b == 9 && a < 8)) << a << ", " << b;
    }
  EXPECT_NE(W.coeff(8, 0), 0.0);
  EXPECT_NE(W.coeff(10, 4), 0.0);  // body 4's equality and body 3's contact, coupled through A
}

// A factor row reached by more than max_density × (number of blocks) blocks: W is not formed, and left
// as it was.
TEST(BlockGram, DeclinesAWTooDenseAndLeavesItUntouched) {
  const SparseMatrix A = iteration_matrix();
  SparseLdlt factor;
  ASSERT_TRUE(factor.factor_positive_definite(A));
  // Four contacts, three of them on body 1: body 1's rows are reached by 3 of the 4 blocks.
  const Matrix H = contact_rows({{0, 1}, {1, 2}, {1, -1}, {3, -1}}, 3, {}, A.cols(), 17);
  const Columns columns = forward_columns(factor, H);
  Eigen::SparseMatrix<double, Eigen::RowMajor> W(2, 2);
  W.insert(1, 0) = 7.0;
  W.makeCompressed();
  BlockGram gram;
  EXPECT_FALSE(gram.assemble(factor, columns.pointers, 3, 4, W, 0.5));
  ASSERT_EQ(W.rows(), 2);
  EXPECT_EQ(W.nonZeros(), 1);
  EXPECT_EQ(W.coeff(1, 0), 7.0);
  // At 0.75 (3 blocks allowed at a row) it is formed.
  EXPECT_TRUE(gram.assemble(factor, columns.pointers, 3, 4, W, 0.75));
  EXPECT_EQ(W.rows(), 12);
}

}  // namespace
}  // namespace csim
