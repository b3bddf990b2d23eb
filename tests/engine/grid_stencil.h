// A test matrix for the sparse factor's users: a 2D grid's 5-point stencil, one unknown a node, plus a
// small mass on the diagonal, so that it is positive definite.
#pragma once

#include "engine/linear_algebra/sparse_ldlt.h"

namespace csim {

inline SparseMatrix grid_stencil(int side, double mass) {
  Triplets t;
  const int n = side * side;
  for (int x = 0; x < side; ++x)
    for (int y = 0; y < side; ++y) {
      const int i = x * side + y;
      t.emplace_back(i, i, mass);
      for (int j : {x + 1 < side ? i + side : -1, y + 1 < side ? i + 1 : -1}) {
        if (j < 0) continue;
        t.emplace_back(i, i, 1.0);
        t.emplace_back(j, j, 1.0);
        t.emplace_back(i, j, -1.0);
        t.emplace_back(j, i, -1.0);
      }
    }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

}  // namespace csim
