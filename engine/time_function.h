// A dimensionless load multiplier λ(t): constant 1, a linear ramp from 0 to 1 over `ramp_time` (s) then
// constant, or a table of (t, λ) points interpolated linearly and held constant beyond its ends.
#pragma once

#include <utility>
#include <vector>

namespace csim {

struct TimeFunction {
  double ramp_time = 0.0;                          // s; 0 = applied at once
  std::vector<std::pair<double, double>> table;    // (s, –), sorted by time; used when not empty

  double operator()(double t) const {
    if (!table.empty()) return tabulated(t);
    if (ramp_time <= 0.0) return 1.0;
    return t <= 0.0 ? 0.0 : (t >= ramp_time ? 1.0 : t / ramp_time);
  }

 private:
  double tabulated(double t) const {
    if (t <= table.front().first) return table.front().second;
    if (t >= table.back().first) return table.back().second;
    std::size_t i = 1;
    while (table[i].first < t) ++i;
    const auto& [t0, y0] = table[i - 1];
    const auto& [t1, y1] = table[i];
    return y0 + (y1 - y0) * (t - t0) / (t1 - t0);
  }
};

}  // namespace csim
