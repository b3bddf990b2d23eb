// The two triangular sweeps of an LDLᵀ solve, L⁻¹ and L⁻ᵀ D⁻¹, over a simplicial factor's column storage
// (CHOLMOD's, sparse_ldlt.h) read by supernodes: runs of columns whose patterns below the diagonal are
// the same (a node's unknowns, a separator), so that a supernode's rows are read once as a list, not
// once per entry.
//
// Why. A simplicial solve reads each entry of L with its row index, 12 bytes an entry; over a factor
// larger than the last-level cache (the FE shoe's L is 44 MB at 52k DOFs), the two sweeps of a step are
// bound by that traffic (docs/solver-measurements.md). Here a supernode's off-diagonal entries are read
// as dense columns of equal length against its row list: 8 bytes an entry, and products over contiguous
// values that the compiler vectorizes. Each sweep reads the storage as one stream: the forward sweep from
// its start, the backward sweep from its end (each supernode, and each column in it, from its end too).
//
// Storage. Column j of L holds its rows ascending with the diagonal first (which holds D_j), at start[j],
// count[j] entries, in rows row[...]: the layout SupernodalLdlt writes and CHOLMOD's simplicial solves
// read. Results agree with a column-by-column sweep at round-off: within a supernode of w > 1 columns the
// off-diagonal updates are summed over its columns first (forward) or as one dot per column (backward).
#pragma once

#include <vector>

namespace csim {

class SupernodalSweeps {
 public:
  // The supernodes of the storage's pattern (which the values do not change): column j + 1 joins j's
  // supernode when it is j's parent and its rows are j's below j.
  void analyse(int n, const int* start, const int* count, const int* row);
  int supernodes() const { return first_column_.empty() ? 0 : static_cast<int>(first_column_.size()) - 1; }
  // x ← L⁻¹ x (x in the factor's order).
  void forward(const int* start, const double* values, double* x) const;
  // x ← L⁻ᵀ D⁻¹ x.
  void backward(const int* start, const double* values, double* x) const;

 private:
  // Supernode s: columns first_column_[s] … first_column_[s + 1] − 1; the rows below its diagonal block,
  // below_[below_start_[s] … below_start_[s + 1]).
  std::vector<int> first_column_, below_start_, below_;
  mutable std::vector<double> work_;  // a supernode's gathered rows below its diagonal block, or their updates
};

}  // namespace csim
