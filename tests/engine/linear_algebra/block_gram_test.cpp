// The sparse Delassus operator by whole blocks (engine/linear_algebra/block_gram.h) against H A⁻¹ Hᵀ
// from dense algebra, on an iteration matrix that couples some bodies and not others: the entries, the
// exact symmetry, and a pattern that holds exactly the blocks of rows moving a common body.
#include "engine/linear_algebra/block_gram.h"

#include <gtest/gtest.h>

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

  std::vector<SparseLdlt::ForwardColumn> forward(m);
  std::vector<const SparseLdlt::ForwardColumn*> columns;
  for (int a = 0; a < m; ++a) {
    std::vector<int> index;
    std::vector<double> value;
    for (int j = 0; j < H.cols(); ++j)
      if (H(a, j) != 0.0) {
        index.push_back(j);
        value.push_back(H(a, j));
      }
    factor.forward(index.data(), value.data(), static_cast<int>(index.size()), forward[a]);
    columns.push_back(&forward[a]);
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor> W;
  block_gram(factor, columns, 3, contacts, W);

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

}  // namespace
}  // namespace csim
