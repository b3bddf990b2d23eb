// The summary of repeated timings the benchmarks print: the median (the upper of the two middle values
// for an even count) and the range.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace csim::bench {

struct Spread {
  double median = NAN, min = NAN, max = NAN;
};

inline Spread spread(std::vector<double> values) {
  if (values.empty()) return {};
  std::sort(values.begin(), values.end());
  return {values[values.size() / 2], values.front(), values.back()};
}

}  // namespace csim::bench
