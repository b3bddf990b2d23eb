// The two triangular sweeps of the FE shoe's factor as a step takes them (engine/linear_algebra/supernodal_sweeps.h;
// run by hand: build/bench/bench_sweeps [repeats]): a forward sweep, then a backward one on its result,
// `repeats` pairs, at 13 122 and 51 842 DOFs (SDNV104's QUAD4 shoe, A = M + h²θ²K, h = 1e-3 s,
// θ = 0.51). Each sweep's median and [min–max] in ms. bench_factor times each sweep alone, repeated,
// where the backward sweep finds what it read last in the cache; here it finds what the forward sweep
// read, as in a step.
//
// A second table puts the step's pass over K and M (engine/linear_algebra/linear_products.h) before each pair, as a
// step does between its backward sweep and the next step's forward sweep, and gives the 51 842 / 13 122
// ratio of each column: whether that pass costs the forward sweep the part of L the backward sweep left
// in the cache, and what the sweeps' own ratio is against target 3's 4.85 (docs/solver-measurements.md,
// "The sparse factor"). The two tables' runs alternate the sizes within each repeat.
#include "bench/shoe_iteration_matrix.h"
#include "engine/linear_algebra/linear_products.h"
#include "engine/linear_algebra/sparse_ldlt.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() * 1e3;
}

void print(const char* name, std::vector<double> times) {
  std::sort(times.begin(), times.end());
  std::printf("  %s %7.3f [%6.3f-%6.3f]", name, times[times.size() / 2], times.front(), times.back());
}

}  // namespace

// One size's factor, its K and M, and the times of the two tables' columns.
struct Size {
  explicit Size(int divisions);
  ShoeMatrices shoe;
  csim::SparseLdlt factor;
  csim::LinearProducts products;
  int n = 0;
  double megabytes_of_L = 0.0;
  std::vector<double> forward, backward, with_products, products_alone, forward_after, backward_after;
};

Size::Size(int divisions) : shoe(shoe_matrices(divisions)) {
  const csim::SparseMatrix A = shoe.iteration();
  factor.factor_positive_definite(A);
  factor.factor_positive_definite(A);  // the step's refactorization: the supernodal path
  n = static_cast<int>(A.rows());
  megabytes_of_L = 8e-6 * factor.factor_nonzeros();
  products = csim::LinearProducts({{0, 0, &shoe.K}}, shoe.M);
}

double median(std::vector<double> times) {
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 101;
  std::vector<std::unique_ptr<Size>> sizes;  // not moved: products points to shoe.K and shoe.M
  for (const int divisions : {80, 160}) sizes.push_back(std::make_unique<Size>(divisions));
  std::vector<csim::Vector> f;
  for (const auto& size : sizes) f.push_back(csim::Vector::LinSpaced(size->n, -1.0, 1.0));
  csim::Vector forward_half, forward_scaled, x, Kq, Kv, Mv, q, v;
  // Within a repeat the sizes alternate; each runs a few steps' sweeps first, so that its factor is in
  // the cache as far as a run of many steps of that size keeps it, and its last is timed.
  constexpr int kPasses = 4;
  std::vector<double> t(5);
  for (int r = 0; r < repeats; ++r) {
    for (std::size_t k = 0; k < sizes.size(); ++k) {
      Size& size = *sizes[k];
      for (int pass = 0; pass < kPasses; ++pass) {
        // The pair alone, its first sweep starting where the last pair's second ended.
        auto start = std::chrono::steady_clock::now();
        size.factor.forward_substitute(f[k], forward_half, forward_scaled);
        t[0] = ms_since(start);
        start = std::chrono::steady_clock::now();
        size.factor.back_substitute(forward_half, x);
        t[1] = ms_since(start);
        // The step's order: the pass over K and M (at the last pair's x), then the pair.
        q = 1e-6 * x;
        v = x;
        start = std::chrono::steady_clock::now();
        size.products.multiply(q, v, nullptr, Kq, Kv, Mv, nullptr);
        t[2] = ms_since(start);
        start = std::chrono::steady_clock::now();
        size.factor.forward_substitute(f[k], forward_half, forward_scaled);
        t[3] = ms_since(start);
        start = std::chrono::steady_clock::now();
        size.factor.back_substitute(forward_half, x);
        t[4] = ms_since(start);
      }
      size.forward.push_back(t[0]);
      size.backward.push_back(t[1]);
      size.products_alone.push_back(t[2]);
      size.forward_after.push_back(t[3]);
      size.backward_after.push_back(t[4]);
      size.with_products.push_back(t[2] + t[3] + t[4]);
    }
  }
  std::printf("forward then backward sweep, %d pairs; ms, median [min-max]\n", repeats);
  for (const auto& size : sizes) {
    std::printf("%7d DOFs (L %.1f MB)", size->n, size->megabytes_of_L);
    print("forward", size->forward);
    print("backward", size->backward);
    std::printf("\n");
  }
  std::printf("\nthe step's order: K and M's pass (K q, K v, M v), then the pair; ms, median of %d\n", repeats);
  std::printf("%9s %9s %9s %9s %9s %9s %9s\n", "DOFs", "products", "forward", "backward", "sweeps", "total",
              "(alone)");
  for (const auto& size : sizes) {
    const double forward = median(size->forward_after), backward = median(size->backward_after);
    std::printf("%9d %9.3f %9.3f %9.3f %9.3f %9.3f %9.3f\n", size->n, median(size->products_alone), forward, backward,
                forward + backward, median(size->with_products), median(size->forward) + median(size->backward));
  }
  const Size &small = *sizes.front(), &large = *sizes.back();
  const auto ratio = [&](const std::vector<double> Size::*times) { return median(large.*times) / median(small.*times); };
  std::printf("%9s %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f   (L: %.2f, DOFs: %.2f, target 3: %.2f)\n", "ratio",
              ratio(&Size::products_alone), ratio(&Size::forward_after), ratio(&Size::backward_after),
              (median(large.forward_after) + median(large.backward_after)) /
                  (median(small.forward_after) + median(small.backward_after)),
              ratio(&Size::with_products),
              (median(large.forward) + median(large.backward)) / (median(small.forward) + median(small.backward)),
              large.megabytes_of_L / small.megabytes_of_L, static_cast<double>(large.n) / small.n,
              std::pow(static_cast<double>(large.n) / small.n, 1.15));
  std::printf("(x sum %.6g)\n", x.sum());
  return 0;
}
