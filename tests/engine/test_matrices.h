// Sparse test matrices for the factorization tests.
#pragma once

#include "engine/bodies/body.h"

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

}  // namespace csim::test
