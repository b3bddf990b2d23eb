#include "engine/linear_algebra/forward_rows.h"

#include <algorithm>

namespace csim {

void ForwardRows::assign(const DelassusCache& cache, const std::vector<int>& slots, int factor_size) {
  if (cache.still_holds(taken_, slots)) return;
  // Counted by row, then filled column by column: each row's entries come in the columns' order.
  std::vector<int> place(factor_size + 1, 0);
  for (const int slot : slots) {
    for (const int i : cache.forward(slot).index) ++place[i + 1];
  }
  rows_.clear();
  start_.assign(1, 0);
  for (int i = 0; i < factor_size; ++i) {
    if (place[i + 1] == 0) continue;
    rows_.push_back(i);
    start_.push_back(start_.back() + place[i + 1]);
  }
  for (std::size_t u = 0; u < rows_.size(); ++u) place[rows_[u]] = start_[u];  // the next free entry of each row
  column_.resize(start_.back());
  value_.resize(start_.back());
  for (int c = 0; c < static_cast<int>(slots.size()); ++c) {
    const SparseLdlt::ForwardColumn& y = cache.forward(slots[c]);
    for (std::size_t k = 0; k < y.index.size(); ++k) {
      const int e = place[y.index[k]]++;
      column_[e] = c;
      value_[e] = y.value[k];
    }
  }
}

void ForwardRows::dots(const Vector& z, std::vector<double>& dots) const {
  dots.assign(taken_.slots.size(), 0.0);
  for (std::size_t u = 0; u < rows_.size(); ++u) {
    const double zi = z(rows_[u]);
    for (int e = start_[u]; e < start_[u + 1]; ++e) dots[column_[e]] += value_[e] * zi;
  }
}

void ForwardRows::add(const std::vector<double>& r, const std::vector<char>& use, Vector& w) const {
  const bool every = std::find(use.begin(), use.end(), 0) == use.end();  // every candidate active
  for (std::size_t u = 0; u < rows_.size(); ++u) {
    double wi = w(rows_[u]);
    for (int e = start_[u]; e < start_[u + 1]; ++e) {
      const int c = column_[e];
      if (every || use[c]) wi += r[c] * value_[e];
    }
    w(rows_[u]) = wi;
  }
}

}  // namespace csim
