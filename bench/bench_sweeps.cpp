// The two triangular sweeps of the FE shoe's factor as a step takes them (engine/supernodal_sweeps.h;
// run by hand: build/bench/bench_sweeps [repeats]): a forward sweep, then a backward one on its result,
// `repeats` pairs, at 13 122 and 51 842 DOFs (SDNV104's QUAD4 shoe, A = M + h²θ²K, h = 1e-3 s,
// θ = 0.51). Each sweep's median and [min–max] in ms. bench_factor times each sweep alone, repeated,
// where the backward sweep finds what it read last in the cache; here it finds what the forward sweep
// read, as in a step.
#include "bench/shoe_iteration_matrix.h"
#include "engine/sparse_ldlt.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() * 1e3;
}

void print(const char* name, std::vector<double>& times) {
  std::sort(times.begin(), times.end());
  std::printf("  %s %7.3f [%6.3f-%6.3f]", name, times[times.size() / 2], times.front(), times.back());
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 101;
  std::printf("forward then backward sweep, %d pairs; ms, median [min-max]\n", repeats);
  for (const int divisions : {80, 160}) {
    const csim::SparseMatrix A = shoe_iteration_matrix(divisions);
    csim::SparseLdlt factor;
    factor.factor_positive_definite(A);
    factor.factor_positive_definite(A);  // the step's refactorization: the supernodal path
    const int n = static_cast<int>(A.rows());
    const csim::Vector f = csim::Vector::LinSpaced(n, -1.0, 1.0);
    csim::Vector forward_half, forward_scaled, x;
    std::vector<double> forward, backward;
    for (int r = 0; r < repeats; ++r) {
      const auto start = std::chrono::steady_clock::now();
      factor.forward_substitute(f, forward_half, forward_scaled);
      forward.push_back(ms_since(start));
      const auto middle = std::chrono::steady_clock::now();
      factor.back_substitute(forward_half, x);
      backward.push_back(ms_since(middle));
    }
    std::printf("%7d DOFs", n);
    print("forward", forward);
    print("backward", backward);
    std::printf("  (x sum %.6g)\n", x.sum());
  }
  return 0;
}
