// The sweeps of an LDLᵀ solve by supernodes (engine/linear_algebra/supernodal_sweeps.h) against dense triangular solves
// with the same L and D, on factors whose supernodes have every width (a grid of two-unknown nodes, a
// random sparse pattern, an arrow with a dense hub, a diagonal), and inside SparseLdlt: its two halves
// compose to CHOLMOD's solve.
#include "engine/linear_algebra/sparse_ldlt.h"
#include "engine/linear_algebra/supernodal_ldlt.h"
#include "engine/linear_algebra/supernodal_sweeps.h"
#include "tests/engine/test_matrices.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace csim {
namespace {

using test::arrow;
using test::from_triplets;
using test::random_sparse;

struct SweepErrors {
  double forward = 0.0, backward = 0.0;
  int supernodes = 0;
};

// Factors A (natural order) into a simplicial storage, then sweeps b both ways by supernodes and
// compares with L⁻¹ b and L⁻ᵀ D⁻¹ b by dense triangular solves (relative, in the largest entry).
SweepErrors sweep_errors(const SparseMatrix& A, std::mt19937& random) {
  const test::SimplicialFactor f = test::simplicial_factor(A);
  EXPECT_TRUE(f.positive);
  if (!f.positive) return {NAN, NAN, 0};  // fails every bound below
  const int n = static_cast<int>(A.rows());
  SupernodalSweeps sweeps;
  sweeps.analyse(n, f.start.data(), f.count.data(), f.row.data());
  SweepErrors errors;
  errors.supernodes = sweeps.supernodes();
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Vector b(n);
  for (int i = 0; i < n; ++i) b(i) = uniform(random);
  Vector x = b;
  sweeps.forward(f.start.data(), f.values.data(), x.data());
  const Vector forward = f.L.triangularView<Eigen::UnitLower>().solve(b);
  errors.forward = (x - forward).lpNorm<Eigen::Infinity>() / forward.lpNorm<Eigen::Infinity>();
  x = b;
  sweeps.backward(f.start.data(), f.values.data(), x.data());
  const Vector backward = f.L.transpose().triangularView<Eigen::UnitUpper>().solve(b.cwiseQuotient(f.D));
  errors.backward = (x - backward).lpNorm<Eigen::Infinity>() / backward.lpNorm<Eigen::Infinity>();
  return errors;
}

TEST(SupernodalSweeps, SolveAsDenseTriangularSolvesOnEveryWidthOfSupernode) {
  std::mt19937 random(17);
  const SweepErrors grid = sweep_errors(test::random_grid(9, random), random);
  EXPECT_LE(grid.forward, 1e-13);
  EXPECT_LE(grid.backward, 1e-13);
  EXPECT_LT(grid.supernodes, 162);  // a node's two unknowns share a supernode: the w > 1 path runs
  for (int trial = 0; trial < 5; ++trial) {
    const SweepErrors e = sweep_errors(random_sparse(120, random), random);
    EXPECT_LE(e.forward, 1e-13);
    EXPECT_LE(e.backward, 1e-13);
  }
  const SweepErrors hub = sweep_errors(arrow(60, 3), random);
  EXPECT_LE(hub.forward, 1e-13);
  EXPECT_LE(hub.backward, 1e-13);
  EXPECT_LT(hub.supernodes, 60);
  Triplets diagonal;
  for (int i = 0; i < 7; ++i) diagonal.emplace_back(i, i, 1.0 + i);
  const SweepErrors alone = sweep_errors(from_triplets(7, diagonal), random);
  EXPECT_EQ(alone.forward, 0.0);
  EXPECT_EQ(alone.backward, 0.0);
  EXPECT_EQ(alone.supernodes, 7);
  // A dense matrix: one supernode of all its columns, nothing below its diagonal block.
  Matrix dense = Matrix::Constant(12, 12, 0.5);
  dense.diagonal().array() += 12.0;
  const SweepErrors one = sweep_errors(SparseMatrix(dense.sparseView()), random);
  EXPECT_EQ(one.supernodes, 1);
  EXPECT_LE(one.forward, 1e-14);
  EXPECT_LE(one.backward, 1e-14);
}

// Nothing to sweep: before any analysis, and for a pattern of no columns.
TEST(SupernodalSweeps, AnEmptyPatternSweepsNothing) {
  SupernodalSweeps sweeps;
  double x = 1.5;
  const int start[1] = {0};
  sweeps.forward(start, nullptr, &x);
  sweeps.backward(start, nullptr, &x);
  EXPECT_EQ(sweeps.supernodes(), 0);
  sweeps.analyse(0, start, nullptr, nullptr);
  sweeps.forward(start, nullptr, &x);
  sweeps.backward(start, nullptr, &x);
  EXPECT_EQ(sweeps.supernodes(), 0);
  EXPECT_EQ(x, 1.5);
}

// Inside SparseLdlt (its ordering, CHOLMOD's storage): the forward and backward halves compose to
// CHOLMOD's whole solve at round-off, before and after a supernodal refactorization of the pattern.
TEST(SupernodalSweeps, HalvesInSparseLdltComposeToItsSolve) {
  std::mt19937 random(23);
  SparseMatrix A = test::random_grid(14, random);
  const int n = static_cast<int>(A.rows());
  const Vector f = Vector::LinSpaced(n, -1.0, 2.0);
  SparseLdlt factor;
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) A.diagonal().array() += 0.3;  // the same pattern: a supernodal refactorization
    ASSERT_TRUE(factor.factor_positive_definite(A));
    EXPECT_EQ(factor.supernodal_factorizations(), pass);
    Vector w, z, x;
    factor.forward_substitute(f, w, z);
    factor.back_substitute(w, x);
    const Vector solved = factor.solve(f);
    EXPECT_LE((x - solved).lpNorm<Eigen::Infinity>(), 1e-12 * solved.lpNorm<Eigen::Infinity>()) << "pass " << pass;
    EXPECT_LE((A * x - f).lpNorm<Eigen::Infinity>(), 1e-12 * f.lpNorm<Eigen::Infinity>()) << "pass " << pass;
  }
}

}  // namespace
}  // namespace csim
