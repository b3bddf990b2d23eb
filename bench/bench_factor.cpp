// The sparse factor of a finite-element iteration matrix (engine/linear_algebra/sparse_ldlt.h) against the mesh size
// (run by hand: OMP_NUM_THREADS=1 build/bench/bench_factor [max divisions] [repeats]).
// SDNV104's QUAD4 shoe, A = M + h²θ² K: entries of L (with D), their memory, the time of one solve
// (median of `repeats`, [min–max]) and per entry of L, the times of its forward half alone
// (forward_substitute, the Moreau–Jean free velocity's; median) and of its backward half alone
// (back_substitute, the update's; median), and the forward columns of the bottom nodes'
// contact rows (those of the bench_fe runs): their mean length (the reach along the elimination tree)
// and time, and the time of all their Delassus entries from the cache (delassus_cache.h), which is
// what the first contact costs, against one full solve per row before.
#include "bench/shoe_iteration_matrix.h"
#include "engine/contact_stage/delassus_cache.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
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
  return 0;
}
