#include "engine/forward_rows.h"

#include <algorithm>

namespace csim {

void ForwardRows::assign(const DelassusCache& cache, const std::vector<int>& slots, int factor_size) {
  if (slots == slots_ && cache.computed_entries() == computed_entries_) return;
  slots_ = slots;
  computed_entries_ = cache.computed_entries();
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
  dots.assign(slots_.size(), 0.0);
  for (std::size_t u = 0; u < rows_.size(); ++u) {
    const double zi = z(rows_[u]);
    for (int e = start_[u]; e < start_[u + 1]; ++e) dots[column_[e]] += value_[e] * zi;
  }
}

void ForwardRows::add(const std::vector<double>& r, const std::vector<char>& use, Vector& w) const {
  if (std::find(use.begin(), use.end(), 0) == use.end()) {  // every column (every candidate active)
    // Two rows at a time: a row's sum is one chain of additions in the columns' order (the bits), and
    // the top separators' rows are reached by every column; two chains hide each other's latency.
    std::size_t u = 0;
    for (; u + 2 <= rows_.size(); u += 2) {
      double w0 = w(rows_[u]), w1 = w(rows_[u + 1]);
      int e0 = start_[u], e1 = start_[u + 1];
      const int end0 = start_[u + 1], end1 = start_[u + 2];
      for (; e0 < end0 && e1 < end1; ++e0, ++e1) {
        w0 += r[column_[e0]] * value_[e0];
        w1 += r[column_[e1]] * value_[e1];
      }
      for (; e0 < end0; ++e0) w0 += r[column_[e0]] * value_[e0];
      for (; e1 < end1; ++e1) w1 += r[column_[e1]] * value_[e1];
      w(rows_[u]) = w0;
      w(rows_[u + 1]) = w1;
    }
    for (; u < rows_.size(); ++u) {
      double wi = w(rows_[u]);
      for (int e = start_[u]; e < start_[u + 1]; ++e) wi += r[column_[e]] * value_[e];
      w(rows_[u]) = wi;
    }
    return;
  }
  for (std::size_t u = 0; u < rows_.size(); ++u) {
    double wi = w(rows_[u]);
    for (int e = start_[u]; e < start_[u + 1]; ++e) {
      const int c = column_[e];
      if (use[c]) wi += r[c] * value_[e];
    }
    w(rows_[u]) = wi;
  }
}

}  // namespace csim
