// Sparse test matrices for the factorization tests, and their factor in a simplicial storage.
#pragma once

#include "engine/bodies/body.h"
#include "engine/linear_algebra/supernodal_ldlt.h"

#include <cmath>
#include <random>

namespace csim::test {

// A random symmetric positive definite matrix with the pattern of a 2D grid's 5-point stencil (an
// elimination tree with long paths, as a mesh has), two unknowns a node, and some random couplings.
inline SparseMatrix random_grid(int side, std::mt19937& random) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const int n = 2 * side * side;
  Triplets t;
  auto couple = [&](int i, int j, double k) {
    t.emplace_back(i, i, k);
    t.emplace_back(j, j, k);
    t.emplace_back(i, j, -k);
    t.emplace_back(j, i, -k);
  };
  for (int x = 0; x < side; ++x)
    for (int y = 0; y < side; ++y) {
      const int node = x * side + y;
      couple(2 * node, 2 * node + 1, 0.5 + 0.4 * uniform(random));
      if (x + 1 < side)
        for (int c = 0; c < 2; ++c) couple(2 * node + c, 2 * (node + side) + c, 1.5 + uniform(random));
      if (y + 1 < side)
        for (int c = 0; c < 2; ++c) couple(2 * node + c, 2 * (node + 1) + c, 1.5 + uniform(random));
      for (int c = 0; c < 2; ++c) t.emplace_back(2 * node + c, 2 * node + c, 1e-2 * (1.2 + uniform(random)));
    }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

inline SparseMatrix from_triplets(int n, const Triplets& t) {
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

// Random couplings (a few per row), diagonally dominant.
inline SparseMatrix random_sparse(int n, std::mt19937& random) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::uniform_int_distribution<int> other(0, n - 1);
  Triplets t;
  Vector diagonal = Vector::Constant(n, 0.1);
  for (int i = 0; i < n; ++i)
    for (int e = 0; e < 2; ++e) {
      const int j = other(random);
      if (j == i) continue;
      const double v = uniform(random);
      t.emplace_back(i, j, v);
      t.emplace_back(j, i, v);
      diagonal(i) += std::abs(v);
      diagonal(j) += std::abs(v);
    }
  for (int i = 0; i < n; ++i) t.emplace_back(i, i, diagonal(i));
  return from_triplets(n, t);
}

// A chain whose last `hub` unknowns couple to every other one (a rigid hub carrying a ring).
inline SparseMatrix arrow(int n, int hub) {
  Triplets t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 4.0 + 0.01 * i);
    if (i > 0 && i < n - hub) {
      t.emplace_back(i, i - 1, -1.0);
      t.emplace_back(i - 1, i, -1.0);
    }
    for (int h = n - hub; h < n; ++h)
      if (h != i) {
        t.emplace_back(i, h, 0.1 / (1 + h - i + n));
        t.emplace_back(h, i, 0.1 / (1 + h - i + n));
      }
  }
  return from_triplets(n, t);
}


// A = L D Lᵀ (A's upper triangle, natural order) by SupernodalLdlt into a storage of L's own pattern
// (CHOLMOD's simplicial layout: column j at start[j], count[j] rows from its diagonal), with L and D
// also dense, for comparisons.
struct SimplicialFactor {
  std::vector<int> start, count, row;
  std::vector<double> values;
  int supernodes = 0;             // SupernodalLdlt's
  bool pattern_matches = false;   // SupernodalLdlt::matches on the storage
  bool positive = false;          // every pivot > 0 (otherwise values hold a partial factor, L and D unset)
  Matrix L;                       // unit lower triangular
  Vector D;
};

inline SimplicialFactor simplicial_factor(const SparseMatrix& A) {
  const SparseMatrix upper = A.triangularView<Eigen::Upper>();
  const int n = static_cast<int>(A.rows());
  SupernodalLdlt factor;
  factor.analyse(n, upper.outerIndexPtr(), upper.innerIndexPtr());
  SimplicialFactor f;
  f.supernodes = factor.supernodes();
  factor.pattern(f.start, f.row);
  f.count.resize(n);
  for (int j = 0; j < n; ++j) f.count[j] = f.start[j + 1] - f.start[j];
  f.pattern_matches = factor.matches(f.start.data(), f.count.data(), f.row.data());
  f.values.assign(f.start[n], 0.0);
  f.positive = factor.factor(upper.valuePtr(), f.start.data(), f.values.data());
  if (!f.positive) return f;
  f.L = Matrix::Identity(n, n);
  f.D.resize(n);
  for (int j = 0; j < n; ++j) {
    f.D(j) = f.values[f.start[j]];
    for (int q = f.start[j] + 1; q < f.start[j + 1]; ++q) f.L(f.row[q], j) = f.values[q];
  }
  return f;
}

}  // namespace csim::test
