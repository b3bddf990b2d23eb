// The Delassus operator W = Yᵀ D⁻¹ Y of the forward columns y_a = L⁻¹ P h_aᵀ of a problem's rows
// (sparse_ldlt.h), stored sparse: W_ab = y_aᵀ D⁻¹ y_b is zero unless the two columns share a row of the
// factor, which for bodies that A does not couple (rigid bodies, points, separate elastic bodies) means
// unless the two rows move a common body. A pile of spheres has a few nonzero 3 × 3 blocks a row, where a
// dense W has m² entries: memory and the Gauss–Seidel sweep then cost O(nonzero blocks).
//
// By blocks (block_pattern.h; the indices a column reaches being its factor rows): a block's columns are
// gathered once onto the factor rows any of them reaches (a panel, zeros where a column does not reach
// the row), and each block (p, q) of the upper triangle is Σ_i over the rows both blocks reach (their
// common groups, whole) of the outer product of the panels' rows, each term y_a(i) y_b(i) / D_i as
// SparseLdlt::delassus_entry forms it, in ascending i: the entries of delassus_entry to the bit (a zero
// of a panel adds ±0 to a sum), and W symmetric to the bit (the lower triangle mirrored).
//
// Cost: the pattern's (block_pattern.h), the panels' O(Σ_p rows × width), then for each block pair a
// merge of the two blocks' lists of groups and P · Q multiply-adds for each row both reach. 962 contacts
// of a settled pile of 200 spheres (8678 block pairs): 7.7 M instructions a W, where one delassus_entry
// an entry of the upper triangle and a binary search for each mirrored one took 44 M; 390 contacts (100
// spheres): 2.4 M, from 12.6 M. Command: valgrind --tool=callgrind --toggle-collect='csim::BlockGram::*'
// build/bench/bench_pile 200 3 1 sparse (its 4 W over 3 steps).
#pragma once

#include "engine/linear_algebra/block_pattern.h"
#include "engine/linear_algebra/sparse_ldlt.h"

#include <Eigen/SparseCore>
#include <vector>

namespace csim {

class BlockGram {
 public:
  // W (columns.size() square) from these forward columns of one factor's rows; dimension: 2 or 3;
  // contacts: how many leading blocks of `dimension` columns are contacts, every later column (an
  // equality row) a block of its own. Returns false, W untouched, when some factor row is reached by
  // more than max_density × (number of blocks) blocks: W would then be dense in at least that fraction
  // of its block rows (the contacts of one elastic body), and the dense storage is faster (the test costs
  // O(Σ |y_a|) at most, and stops at the first such row). The work space is kept for the next call.
  bool assemble(const SparseLdlt& factor, const std::vector<const SparseLdlt::ForwardColumn*>& columns,
                int dimension, int contacts, Eigen::SparseMatrix<double, Eigen::RowMajor>& W,
                double max_density = 1.0);

 private:
  BlockPattern pattern_;
  std::vector<const std::vector<int>*> reach_;
  std::vector<long> panel_start_;  // each block's panel: its rows' values, by factor row then column
  std::vector<double> panels_;
};

}  // namespace csim
