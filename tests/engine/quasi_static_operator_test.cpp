// The quasi-static stepper's iteration operator (engine/steppers/quasi_static_operator.h) against dense
// algebra: rows over q mapped to the unknowns z by T (H_z = H T), W = H_z K⁻¹ H_zᵀ, the two halves of a
// solve b = H_z K⁻¹ f and Δz = K⁻¹ (f + H_zᵀ r), and the response K⁻¹ H_zᵀ r, each to 1e-12 of its size
// (the factor's round-off on a well-conditioned K).
#include "engine/steppers/quasi_static_operator.h"

#include <gtest/gtest.h>

namespace csim {
namespace {

// K_z of a chain of n springs held at one end: tridiagonal, positive definite.
SparseMatrix chain(int n) {
  Triplets t;
  for (int i = 0; i < n; ++i) {
    const double k = 1.0 + 0.1 * i;
    t.emplace_back(i, i, k);
    if (i > 0) {
      t.emplace_back(i - 1, i - 1, k);
      t.emplace_back(i - 1, i, -k);
      t.emplace_back(i, i - 1, -k);
    }
  }
  SparseMatrix K(n, n);
  K.setFromTriplets(t.begin(), t.end());
  return K;
}

double relative(const Matrix& a, const Matrix& b) {
  return (a - b).lpNorm<Eigen::Infinity>() / b.lpNorm<Eigen::Infinity>();
}

TEST(QuasiStaticOperator, MapsRowsToTheUnknownsAndSolvesOnTheFactor) {
  // 10 coordinates q over 7 unknowns z: q0 prescribed (no unknown), q1…q7 = z0…z6, q8 and q9 carried by
  // z6 with levers (a tie's rows of T).
  const int n = 10, nz = 7;
  Triplets t;
  for (int i = 1; i <= 7; ++i) t.emplace_back(i, i - 1, 1.0);
  t.emplace_back(8, 6, 0.5);
  t.emplace_back(9, 6, -2.0);
  t.emplace_back(9, 5, 0.25);
  SparseRowMatrix T(n, nz);
  T.setFromTriplets(t.begin(), t.end());
  const SparseMatrix K = chain(nz);
  SparseLdlt factor;
  ASSERT_TRUE(factor.factor_positive_definite(K));
  QuasiStaticOperator iteration(factor, T);

  // Two contacts of two rows: one on q0 (prescribed: its rows reach z only through the others), q2, q3;
  // one on q8 and q9.
  std::vector<SparseRow> rows(4);
  rows[0].add(0, 1.0), rows[0].add(2, -0.6), rows[0].add(3, 0.8);
  rows[1].add(2, 0.8), rows[1].add(3, 0.6);
  rows[2].add(8, 1.0), rows[2].add(9, 0.3);
  rows[3].add(9, -1.0);
  ProblemRows problem_rows;
  problem_rows.dimension = 2;
  for (const SparseRow& row : rows) problem_rows.contact.push_back(&row);
  Matrix H = Matrix::Zero(4, n);
  for (int a = 0; a < 4; ++a) rows[a].scatter(1.0, H.row(a));
  const Matrix H_z = H * Matrix(T);
  const Matrix K_inverse = Matrix(K).inverse();

  iteration.gather(problem_rows);
  EXPECT_LE(relative(iteration.reduced_rows(), H_z), 1e-15);
  Matrix W;
  iteration.delassus(problem_rows, W);
  EXPECT_LE(relative(W, H_z * K_inverse * H_z.transpose()), 1e-12);

  const Vector f = Vector::LinSpaced(nz, -1.0, 2.0), r = Vector::LinSpaced(4, 0.5, -0.7);
  Vector b, dz;
  iteration.load_term(f, b);
  EXPECT_LE(relative(b, H_z * K_inverse * f), 1e-12);
  iteration.increment(r, dz);
  EXPECT_LE(relative(dz, K_inverse * (f + H_z.transpose() * r)), 1e-12);
  Vector v = Vector::Ones(nz);
  iteration.add_response(problem_rows, r, v);
  EXPECT_LE(relative(v, Vector::Ones(nz) + K_inverse * H_z.transpose() * r), 1e-12);
  Vector u;
  iteration.apply_rows(problem_rows, f, u);
  EXPECT_LE(relative(u, H_z * f), 1e-15);

  // The same number of rows, others at the next gather: the entries the last one wrote are cleared, not
  // carried over.
  problem_rows.contact = {&rows[2], &rows[3], &rows[0], &rows[1]};
  iteration.gather(problem_rows);
  Matrix swapped(4, nz);
  swapped << H_z.bottomRows(2), H_z.topRows(2);
  EXPECT_LE(relative(iteration.reduced_rows(), swapped), 1e-15);
}

}  // namespace
}  // namespace csim
