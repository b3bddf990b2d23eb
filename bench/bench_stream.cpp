// This host's memory read rate, the floor against which the FE sweeps' times are read
// (docs/solver-measurements.md, "The host's memory"; run by hand: build/bench/bench_stream
// [repeats]). An array of doubles is summed in eight independent sums, ascending and descending, each
// read after a 256 MB array has pushed it out of the caches; GB/s of the median of `repeats` reads
// [min–max]. Then the cache as one core sees it: arrays of 1 to 64 MB, each summed ascending `repeats`
// times in a row, so that each read finds in the cache what of the last one stayed there.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

double sum_of(const std::vector<double>& a, bool descending) {
  double s[8] = {};
  const long n = static_cast<long>(a.size()) / 8 * 8;
  if (descending) {
    for (long i = n - 8; i >= 0; i -= 8)
      for (int k = 0; k < 8; ++k) s[k] += a[i + k];
  } else {
    for (long i = 0; i < n; i += 8)
      for (int k = 0; k < 8; ++k) s[k] += a[i + k];
  }
  return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7]));
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 9;
  std::vector<double> flush(256L << 17, 1.0);  // 256 MB
  double sink = 0.0;
  std::printf("%8s %24s %24s\n", "MB", "ascending GB/s", "descending GB/s");
  for (const long megabytes : {8L, 29L, 64L}) {
    std::vector<double> a(megabytes << 17, 1.0);
    std::printf("%8ld", megabytes);
    for (const bool descending : {false, true}) {
      std::vector<double> rates;
      for (int r = 0; r < repeats; ++r) {
        sink += sum_of(flush, false);
        const auto start = std::chrono::steady_clock::now();
        sink += sum_of(a, descending);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        rates.push_back(static_cast<double>(a.size()) * 8.0 / seconds * 1e-9);
      }
      std::sort(rates.begin(), rates.end());
      std::printf(" %8.1f [%5.1f-%5.1f]   ", rates[rates.size() / 2], rates.front(), rates.back());
    }
    std::printf("\n");
  }
  std::printf("\n%8s %24s\n", "MB", "read again GB/s");
  for (const long megabytes : {1L, 4L, 8L, 12L, 16L, 20L, 24L, 29L, 40L, 64L}) {
    std::vector<double> a(megabytes << 17, 1.0);
    sink += sum_of(a, false);
    std::vector<double> rates;
    for (int r = 0; r < repeats; ++r) {
      const auto start = std::chrono::steady_clock::now();
      sink += sum_of(a, false);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      rates.push_back(static_cast<double>(a.size()) * 8.0 / seconds * 1e-9);
    }
    std::sort(rates.begin(), rates.end());
    std::printf("%8ld %8.1f [%5.1f-%5.1f]\n", megabytes, rates[rates.size() / 2], rates.front(), rates.back());
  }
  return sink == 0.0 ? 1 : 0;  // the sums are used
}
