// The sparse factor of a finite-element iteration matrix (engine/linear_algebra/sparse_ldlt.h) against the mesh size
// (run by hand: OMP_NUM_THREADS=1 build/bench/bench_factor [max divisions] [repeats]).
// SDNV104's QUAD4 shoe, A = M + h²θ² K: entries of L (with D), their memory, the time of one solve
// (median of `repeats`, [min–max]) and per entry of L, the times of its forward half alone
// (forward_substitute, the Moreau–Jean free velocity's; median) and of its backward half alone
// (back_substitute, the update's; median), and the forward columns of the bottom nodes'
// contact rows (those of the bench_fe runs): their mean length (the reach along the elimination tree)
// and time, and the time of all their Delassus entries from the cache (delassus_cache.h), which is
// what the first contact costs, against one full solve per row before.
//
// A second table times SparseLdlt::forward, y = L⁻¹ P hᵀ of a row h with three nonzeros (a bottom
// node's two unknowns and its neighbour's vertical one), by our kernel (the reach along the elimination
// tree, sparse_ldlt.h) and by CHOLMOD's sparse solve on the same factor (cholmod_solve2, CHOLMOD_L with
// the pattern of P hᵀ as Bset and the reach returned as Xset; P is applied by SparseLdlt, the factor
// being of P A Pᵀ; SparseLdlt::Kernels::cholmod): time per column, median [min–max] over repeats that
// alternate the two. `bench_factor forward ours|cholmod DIVISIONS COLUMNS` computes only one kernel's
// columns, for an instruction count of SparseLdlt::forward alone:
//   valgrind --tool=callgrind --toggle-collect='csim::SparseLdlt::forward(*' build/bench/bench_factor forward ours 80 1000
// (the collected instructions of 600 columns less those of 200, / 400). Measured on Debian bookworm,
// CHOLMOD 3.0.14, `bench_factor 160 41` (one quiet run; on a loaded host the spreads reach 2×):
//    dofs  reach  ours ns/column [min-max]  CHOLMOD ns/column [min-max]  ratio  instructions ours / CHOLMOD
//   13122    470     31 847 [30 719-43 234]      35 945 [34 728-38 875]   1.13     613 096 / 648 577
//   51842    944   117 322 [115 143-193 340]   124 774 [119 555-212 530]   1.06   2 406 179 / 2 482 775
#include "bench/shoe_iteration_matrix.h"
#include "engine/contact_stage/delassus_cache.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The rows of the forward table: node i of the bottom row, h = e_{2i+1} + 0.5 e_{2i} − 0.25 e_{2(i+1)+1}.
struct Row {
  int index[3];
  double value[3];
};

std::vector<Row> bottom_rows(int divisions) {
  std::vector<Row> rows;
  for (int node = 0; node < divisions; ++node) rows.push_back({{2 * node + 1, 2 * node, 2 * (node + 1) + 1}, {1.0, 0.5, -0.25}});
  return rows;
}

// Every row's forward column; the mean number of entries in them.
double forward_all(const csim::SparseLdlt& factor, const std::vector<Row>& rows, csim::SparseLdlt::ForwardColumn& y) {
  double entries = 0.0;
  for (const Row& row : rows) {
    factor.forward(row.index, row.value, 3, y);
    entries += static_cast<double>(y.index.size());
  }
  return entries / static_cast<double>(rows.size());
}

// The forward table: ours against CHOLMOD's sparse solve, each repeat timing both, in alternating order.
void forward_table(int largest, int repeats) {
  std::printf("\nSparseLdlt::forward, y = L⁻¹ P hᵀ, h with 3 nonzeros (bottom rows): ours against cholmod_solve2 "
              "(CHOLMOD_L, Bset/Xset) on the same factor; ns per column, median [min-max] of %d repeats\n", repeats);
  std::printf("%5s %7s %6s %10s %26s %26s %7s\n", "div", "dofs", "rows", "mean reach", "ours", "CHOLMOD", "ratio");
  for (int divisions = 20; divisions <= largest; divisions *= 2) {
    const csim::SparseMatrix A = shoe_iteration_matrix(divisions);
    csim::SparseLdlt ours, cholmod(csim::SparseLdlt::Kernels::cholmod);
    ours.factor_positive_definite(A);
    cholmod.factor_positive_definite(A);
    const std::vector<Row> rows = bottom_rows(divisions);
    csim::SparseLdlt::ForwardColumn y;
    const double reach = forward_all(ours, rows, y);
    if (forward_all(cholmod, rows, y) != reach) std::printf("the two reaches differ\n");
    std::vector<double> times[2];
    for (int r = 0; r < repeats; ++r)
      for (int k = 0; k < 2; ++k) {
        const int which = (r + k) % 2;
        const auto start = std::chrono::steady_clock::now();
        forward_all(which == 0 ? ours : cholmod, rows, y);
        times[which].push_back(seconds_since(start) * 1e9 / static_cast<double>(rows.size()));
      }
    for (auto& t : times) std::sort(t.begin(), t.end());
    const double ours_median = times[0][times[0].size() / 2], cholmod_median = times[1][times[1].size() / 2];
    std::printf("%5d %7d %6zu %10.0f %9.0f [%6.0f-%7.0f] %9.0f [%6.0f-%7.0f] %7.2f\n", divisions, static_cast<int>(A.rows()),
                rows.size(), reach, ours_median, times[0].front(), times[0].back(), cholmod_median, times[1].front(),
                times[1].back(), cholmod_median / ours_median);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::strcmp(argv[1], "forward") == 0) {  // one kernel's columns alone (see the header)
    const bool ours = argc > 2 && std::strcmp(argv[2], "ours") == 0;
    const int divisions = argc > 3 ? std::atoi(argv[3]) : 80, columns = argc > 4 ? std::atoi(argv[4]) : 1000;
    csim::SparseLdlt factor(ours ? csim::SparseLdlt::Kernels::ours_where_supported : csim::SparseLdlt::Kernels::cholmod);
    factor.factor_positive_definite(shoe_iteration_matrix(divisions));
    const std::vector<Row> rows = bottom_rows(divisions);
    csim::SparseLdlt::ForwardColumn y;
    double entries = 0.0;
    for (int k = 0; k < columns; ++k) {
      const Row& row = rows[k % rows.size()];
      factor.forward(row.index, row.value, 3, y);
      entries += static_cast<double>(y.index.size());
    }
    std::printf("%s: %d columns, mean reach %.0f\n", ours ? "ours" : "CHOLMOD", columns, entries / columns);
    return 0;
  }
  const int largest = argc > 1 ? std::atoi(argv[1]) : 160;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 21;
  std::printf("SDNV104 QUAD4 shoe, A = M + h²θ²K (h = 1e-3 s, θ = 0.51); times in ms\n");
  std::printf("%5s %7s %10s %8s %22s %8s %9s %9s %8s %11s %11s %12s\n", "div", "dofs", "L entries", "L MB",
              "solve [min-max]", "ns/entry", "forward", "backward", "rows", "mean reach", "forward/row", "W all rows");
  for (int divisions = 10; divisions <= largest; divisions *= 2) {
    const csim::SparseMatrix A = shoe_iteration_matrix(divisions);
    csim::SparseLdlt factor;
    factor.factor_positive_definite(A);
    const int n = static_cast<int>(A.rows());
    csim::Vector x = csim::Vector::LinSpaced(n, -1.0, 1.0);
    std::vector<double> solves;
    for (int r = 0; r < repeats; ++r) {
      const auto start = std::chrono::steady_clock::now();
      factor.solve_in_place(x);
      solves.push_back(seconds_since(start) * 1e3);
    }
    std::sort(solves.begin(), solves.end());
    std::vector<double> forward;
    csim::Vector forward_half, forward_scaled;
    for (int r = 0; r < repeats; ++r) {
      const auto start = std::chrono::steady_clock::now();
      factor.forward_substitute(x, forward_half, forward_scaled);
      forward.push_back(seconds_since(start) * 1e3);
    }
    std::sort(forward.begin(), forward.end());
    std::vector<double> backward;
    csim::Vector backward_solution;
    for (int r = 0; r < repeats; ++r) {
      const auto start = std::chrono::steady_clock::now();
      factor.back_substitute(x, backward_solution);
      backward.push_back(seconds_since(start) * 1e3);
    }
    std::sort(backward.begin(), backward.end());
    const double entries = factor.factor_nonzeros();
    // The bottom nodes' two rows (x and y of a node at y = 0; the mesh numbers nodes row by row, the
    // bottom row first, two unknowns a node).
    const int nodes = divisions + 1;
    const auto start = std::chrono::steady_clock::now();
    csim::DelassusCache cache;
    cache.begin(factor);
    for (int node = 0; node < nodes; ++node)
      for (int k = 0; k < 2; ++k) {
        const int index = 2 * node + (k == 0 ? 1 : 0);
        const double one = 1.0;
        cache.slot({0, {0, 1, node}, k}, &index, &one, 1);
      }
    const double forward_time = seconds_since(start);
    cache.finish();
    const double all_time = seconds_since(start);
    const double rows = 2.0 * nodes;
    std::printf("%5d %7d %10.0f %8.1f %8.3f [%5.3f-%6.3f] %8.2f %9.3f %9.3f %8.0f %11.0f %11.4f %12.1f\n", divisions, n,
                entries, entries * 12.0 / 1e6, solves[solves.size() / 2], solves.front(), solves.back(),
                solves[solves.size() / 2] * 1e6 / entries, forward[forward.size() / 2], backward[backward.size() / 2], rows, cache.stored_values() / rows,
                forward_time / rows * 1e3, all_time * 1e3);
  }
  forward_table(largest, repeats);
  return 0;
}
