// The forward columns y_c = L⁻¹ P h_cᵀ of a list of contact and equality rows (delassus_cache.h), stored
// a second time by the factor's rows, so that the two halves' uses (forward_columns.h) of them are each one pass in
// the factor's order:
//   - the dots y_cᵀ z of every row (h A⁻¹ f seen by the row, z = D⁻¹ L⁻¹ P h f), before the contact solve;
//   - w + Y r (the backward half's right-hand side), after it.
// Why. Column by column, each dot gathers z at its column's rows and each column scatters into w: at 52k
// DOFs 322 columns of about 900 rows each, mostly the same top separators, read from a 415 KB vector
// that no longer stays in the 1 MB L2 with the rest of the step (docs/solver-measurements.md, "The
// sparse factor"). By rows, z and w are read once, ascending, and the sums sit in a few KB.
//
// Bits. A dot sums its column's rows ascending from zero, and an entry of w + Y r adds its columns in the
// list's order: the operations of SparseLdlt::dot and add_scaled column by column, in the same order, so
// the results are the same to the bit.
#pragma once

#include "engine/contact_stage/delassus_cache.h"

#include <vector>

namespace csim {

class ForwardRows {
 public:
  // Stores the columns of these slots, in this order, unless those stored still hold
  // (DelassusCache::still_holds: the same slots, no forward column recomputed since).
  void assign(const DelassusCache& cache, const std::vector<int>& slots, int factor_size);
  int columns() const { return static_cast<int>(taken_.slots.size()); }
  // dots[c] = y_cᵀ z for every column c.
  void dots(const Vector& z, std::vector<double>& dots) const;
  // w(i) += r[c] y_c(i) for the columns c with use[c], in the columns' order (w in the factor's order).
  void add(const std::vector<double>& r, const std::vector<char>& use, Vector& w) const;

 private:
  DelassusCache::Taken taken_;  // the slots stored
  std::vector<int> rows_;    // the rows any column reaches, ascending
  std::vector<int> start_;   // row u's entries: start_[u] … start_[u + 1] − 1
  std::vector<int> column_;  // each entry's column (its place in the list), ascending within a row
  std::vector<double> value_;
};

}  // namespace csim
