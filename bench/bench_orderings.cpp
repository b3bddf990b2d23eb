// The fill of the FE shoe's factor under each fill-reducing ordering, against the mesh size (run by
// hand: build/bench/bench_orderings [max divisions]; docs/solver-measurements.md, "The sparse factor").
// SDNV104's QUAD4 shoe, A = M + h²θ²K on a (d + 1) × (d + 1) grid of two-unknown nodes: entries of L (D
// included) and flops of its factorization under CHOLMOD's AMD, METIS and NESDIS orderings (each
// postordered, as engine/linear_algebra/sparse_ldlt.cpp orders), and under a geometric nested dissection of the grid,
// the textbook ordering for it (George 1973): a middle grid line as separator, each half dissected in
// turn, the separators last. For each ordering, the growth of L's entries from the previous size and its
// slope against the unknowns' growth: what the two sweeps of a step read.
#include "bench/shoe_iteration_matrix.h"

#include <cholmod.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

// The nodes of the grid's block [x0, x1) × [y0, y1) in nested-dissection order (node x + side · y).
void dissect(int x0, int x1, int y0, int y1, int side, std::vector<int>& order) {
  const int width = x1 - x0, height = y1 - y0;
  if (width <= 0 || height <= 0) return;
  if (width * height == 1) {
    order.push_back(x0 + side * y0);
    return;
  }
  if (width >= height) {
    const int middle = x0 + width / 2;
    dissect(x0, middle, y0, y1, side, order);
    dissect(middle + 1, x1, y0, y1, side, order);
    for (int y = y0; y < y1; ++y) order.push_back(middle + side * y);
  } else {
    const int middle = y0 + height / 2;
    dissect(x0, x1, y0, middle, side, order);
    dissect(x0, x1, middle + 1, y1, side, order);
    for (int x = x0; x < x1; ++x) order.push_back(x + side * middle);
  }
}

struct Fill {
  double entries = 0.0, flops = 0.0;
};

}  // namespace

int main(int argc, char** argv) {
  const int largest = argc > 1 ? std::atoi(argv[1]) : 160;
  cholmod_common common;
  cholmod_start(&common);
  common.nmethods = 1;
  common.postorder = 1;
  const char* names[] = {"AMD", "METIS", "NESDIS", "grid ND"};
  std::printf("SDNV104 QUAD4 shoe, A = M + h²θ²K: entries of L (millions) and, from the previous size, their "
              "growth and its slope against the unknowns'\n%5s %7s", "div", "dofs");
  for (const char* name : names) std::printf(" %28s", name);
  std::printf("\n");
  std::vector<Fill> previous;
  int previous_n = 0;
  for (int divisions = 40; divisions <= largest; divisions *= 2) {
    csim::SparseMatrix A = shoe_iteration_matrix(divisions);
    A.makeCompressed();
    const int n = static_cast<int>(A.rows()), side = divisions + 1;
    if (n != 2 * side * side) {
      std::fprintf(stderr, "bench_orderings: %d unknowns, not two a node of a %d × %d grid\n", n, side, side);
      return 1;
    }
    cholmod_sparse lower{};
    lower.nrow = lower.ncol = n;
    lower.nzmax = A.nonZeros();
    lower.p = A.outerIndexPtr();
    lower.i = A.innerIndexPtr();
    lower.x = A.valuePtr();
    lower.stype = -1;
    lower.itype = CHOLMOD_INT;
    lower.xtype = CHOLMOD_REAL;
    lower.dtype = CHOLMOD_DOUBLE;
    lower.sorted = lower.packed = 1;
    std::vector<Fill> fills;
    for (const int method : {CHOLMOD_AMD, CHOLMOD_METIS, CHOLMOD_NESDIS}) {
      common.method[0].ordering = method;
      cholmod_factor* symbolic = cholmod_analyze(&lower, &common);
      fills.push_back({common.lnz, common.fl});
      cholmod_free_factor(&symbolic, &common);
    }
    std::vector<int> nodes, permutation(n);
    dissect(0, side, 0, side, side, nodes);
    for (int k = 0; k < side * side; ++k) {
      permutation[2 * k] = 2 * nodes[k];
      permutation[2 * k + 1] = 2 * nodes[k] + 1;
    }
    common.method[0].ordering = CHOLMOD_GIVEN;
    cholmod_factor* symbolic = cholmod_analyze_p(&lower, permutation.data(), nullptr, 0, &common);
    fills.push_back({common.lnz, common.fl});
    cholmod_free_factor(&symbolic, &common);
    std::printf("%5d %7d", divisions, n);
    for (std::size_t k = 0; k < fills.size(); ++k) {
      if (previous.empty()) {
        std::printf(" %8.3f (%.3g flops)          ", fills[k].entries * 1e-6, fills[k].flops);
      } else {
        const double growth = fills[k].entries / previous[k].entries;
        std::printf(" %8.3f ×%.3f slope %.3f    ", fills[k].entries * 1e-6, growth,
                    std::log(growth) / std::log(static_cast<double>(n) / previous_n));
      }
    }
    std::printf("\n");
    previous = fills;
    previous_n = n;
  }
  cholmod_finish(&common);
  return 0;
}
