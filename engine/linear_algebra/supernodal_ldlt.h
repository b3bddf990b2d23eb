// The numeric LDLᵀ factorization of a symmetric matrix M = L D Lᵀ by supernodes, written into the
// column storage of a simplicial factor (CHOLMOD's, sparse_ldlt.h), for refactorizations of one pattern.
//
// Why. CHOLMOD's simplicial factorization is up-looking: it forms L row by row, each row by a sparse
// triangular solve that reads L's columns through their row indices one entry at a time. Its
// supernodal one works on dense blocks but through BLAS, which Debian's reference BLAS makes slower on
// blocks of 2 to 50 columns than the simplicial one. Here the columns of L that share their pattern
// below the diagonal (a supernode: a node's two or three unknowns, a separator) are treated together
// in a dense block, right-looking: the supernode's columns are finished by dense column operations,
// then its update L_s D_s L_sᵀ below its diagonal block is formed by a product compiled for small
// blocks and subtracted from the later supernodes' blocks through relative row positions, which the
// pattern alone decides (found once, by analyse). The blocks are then copied out to the simplicial
// storage. Measurements: docs/rolling.md.
//
// Storage. Column j of L holds its entries in rows ascending, the diagonal first (holding D_j), at
// start[j]: CHOLMOD's simplicial LDLᵀ layout, so that its solves read what is written here. The pattern
// is the symbolic one of M's (no entry dropped); matches() says whether a given storage has it.
//
// M is given as its upper triangle by columns (rows i ≤ j in column j, ascending), as triu(P A Pᵀ) is
// kept by SparseLdlt; no ordering is done here. Results agree with CHOLMOD's at round-off (the sums run
// in another order).
#pragma once

#include <vector>

namespace csim {

class SupernodalLdlt {
 public:
  // The elimination tree, the pattern of L and its supernodes, for the pattern of triu(M).
  void analyse(int n, const int* upper_start, const int* upper_row);
  // Whether column j of the storage at start, count and row holds exactly this pattern's rows.
  bool matches(const int* start, const int* count, const int* row) const;
  // L and D of M (values at the pattern given to analyse) into x at start; false at the first pivot
  // that is not > 0 (x then holds a partial factor).
  bool factor(const double* upper_value, const int* start, double* x);

  // L's pattern by columns, each column's rows ascending from its diagonal (start has n + 1 entries).
  void pattern(std::vector<int>& start, std::vector<int>& row) const;
  int supernodes() const { return static_cast<int>(first_column_.size()) - 1; }

 private:
  // Supernode s: columns first_column_[s] … first_column_[s + 1] − 1; its rows (the first ones its own
  // columns) rows_[row_start_[s] … row_start_[s + 1]).
  std::vector<int> first_column_, row_start_, rows_;
  std::vector<int> supernode_of_;  // by column
  // Supernode s's dense block (its rows × its columns, by columns; D on the diagonal, the strict upper
  // triangle unused) at block_start_[s] in blocks_; upper entry q of M (row i ≤ column j) at
  // entry_position_[q] there (column i, row j).
  std::vector<long> block_start_, entry_position_;
  std::vector<double> blocks_;
  // The columns a supernode's update goes to, in groups by target supernode (its update's columns
  // first … last − 1, below the diagonal block): the target's column J starts at origin + J · rows in
  // blocks_, and the positions in the target's rows of the update's rows from the group's first on are
  // at relative_[at].
  struct Group {
    int first, last, rows;
    long origin, at;
  };
  std::vector<int> group_start_;  // by supernode, into groups_
  std::vector<Group> groups_;
  std::vector<int> relative_;
  std::vector<double> scaled_, update_;  // work: L_s D_s below the diagonal block, and L_s D_s L_sᵀ there
};

}  // namespace csim
