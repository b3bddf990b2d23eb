// The pattern of a Delassus operator W stored sparse by whole blocks (contact/friction_contact_problem.h,
// DelassusStorage::sparse), from what each of its columns reaches: W_ab can be nonzero only when columns
// a and b reach a common index (a common row of a sparse factor, block_gram.h; a common unknown of the
// velocity response, the generalized-α operator). For bodies that the iteration matrix does not couple,
// two rows reach a common index only when they move a common body: a pile of spheres has a few nonzero
// 3 × 3 blocks a row, where a dense W has m² entries.
//
// Blocks: the first dimension · contacts columns are the contacts' rows, `dimension` each, every later
// one (an equality row) a block of its own; two blocks any of whose columns reach a common index get all
// their entries (zeros included), the others none. The rows compressed, filled in order, each entry of
// the upper triangle computed once and mirrored: W is symmetric to the bit.
//
// Cost: the indices the columns reach, each with the list of blocks reaching it (O(Σ |reach_a|)), then
// one call of `entry` for each entry of the upper triangle of the pattern.
#pragma once

#include <Eigen/SparseCore>
#include <vector>

namespace csim {

class BlockPattern {
 public:
  // The blocks that share an index with each block, from reach[a] (the indices in [0, size) that column
  // a reaches; a repeated one counts once). False, the pattern left empty, when some index is reached by
  // more than max_density × (number of blocks) blocks: W would then be dense in at least that fraction of
  // its block rows (the contacts of one elastic body), and the dense storage is faster (the test costs
  // O(Σ |reach_a|) at most, and stops at the first such index).
  bool build(int size, const std::vector<const std::vector<int>*>& reach, int dimension, int contacts,
             double max_density = 1.0);

  // W (columns square) on this pattern: W_ab = entry(a, b) for a ≤ b, mirrored below.
  template <class Entry>
  void fill(Eigen::SparseMatrix<double, Eigen::RowMajor>& W, Entry&& entry) const {
    W.resize(columns_, columns_);
    W.reserve(nonzeros_);
    for (int block = 0; block < blocks_; ++block)
      for (int a = first_column(block); a < first_column(block) + width(block); ++a) {
        W.startVec(a);
        for (const int other : neighbours_[block])
          for (int b = first_column(other); b < first_column(other) + width(other); ++b)
            W.insertBack(a, b) = b < a ? W.coeff(b, a) : entry(a, b);
      }
    W.finalize();
  }

 private:
  int block_of(int a) const { return a < contact_columns_ ? a / dimension_ : contacts_ + (a - contact_columns_); }
  int first_column(int block) const {
    return block < contacts_ ? dimension_ * block : contact_columns_ + (block - contacts_);
  }
  int width(int block) const { return block < contacts_ ? dimension_ : 1; }

  int columns_ = 0, dimension_ = 3, contacts_ = 0, contact_columns_ = 0, blocks_ = 0;
  long nonzeros_ = 0;
  std::vector<std::vector<int>> neighbours_;  // each block's, itself included, ascending
  std::vector<std::pair<int, int>> reached_;  // (index, block), work space
  std::vector<int> count_, last_block_;       // the density test's, work space
};

}  // namespace csim
