// The pattern of a Delassus operator W stored sparse by whole blocks (contact/friction_contact_problem.h,
// DelassusStorage::sparse), from what each of its columns reaches: W_ab can be nonzero only when columns
// a and b reach a common index (a common row of a sparse factor, block_gram.h; a common unknown of the
// velocity response, the generalized-α operator). For bodies that the iteration matrix does not couple,
// two rows reach a common index only when they move a common body: a pile of spheres has a few nonzero
// 3 × 3 blocks a row, where a dense W has m² entries.
//
// Blocks: the first dimension · contacts columns are the contacts' rows, `dimension` each, every later
// one (an equality row) a block of its own; two blocks any of whose columns reach a common index get all
// their entries (zeros included), the others none. The rows compressed, each block of the upper triangle
// computed once and written to its place and to its mirror's (their offsets in W's storage follow from
// the pattern, no search): W is symmetric to the bit.
//
// Groups: consecutive indices that the same blocks reach form a group (AMD's supervariables, at the
// level of the blocks): a rigid body's six unknowns, or its factor rows, are one, so that a block's
// neighbours are the union of its groups' lists of blocks (a merge of two lists for a contact between
// two bodies), and a product of two blocks' columns runs over their common groups' indices whole.
//
// Cost: O(Σ |reach_a| + size) for the blocks reaching each index and the groups (counting sorts, no
// comparison sort), then each block's neighbours (merged from its groups' lists when it has at most two,
// else marked and sorted), and the filling of W's storage: one call of `block` for each block of the
// upper triangle of the pattern. 962 contacts of a settled pile of 200 spheres (200 groups): 1.3 M
// instructions a pattern, where a sort of the (index, block) pairs and of each block's list took 16 M
// (callgrind, see block_gram.h).
#pragma once

#include <Eigen/SparseCore>
#include <algorithm>
#include <span>
#include <vector>

namespace csim {

class BlockPattern {
 public:
  static constexpr int kMaxWidth = 3;  // a contact's rows in 3D

  // The blocks that share an index with each block, from reach[a] (the indices in [0, size) that column
  // a reaches; a repeated one counts once); dimension in [1, kMaxWidth]. False, the pattern left empty,
  // when some index is reached by more than max_density × (number of blocks) blocks: W would then be
  // dense in at least that fraction of its block rows (the contacts of one elastic body), and the dense
  // storage is faster (the test costs O(Σ |reach_a|) at most, and stops at the first such index).
  bool build(int size, const std::vector<const std::vector<int>*>& reach, int dimension, int contacts,
             double max_density = 1.0);

  int blocks() const { return blocks_; }
  int first_column(int block) const {
    return block < contacts_ ? dimension_ * block : contact_columns_ + (block - contacts_);
  }
  int width(int block) const { return block < contacts_ ? dimension_ : 1; }
  // The groups: runs of consecutive indices that the same blocks reach (a body's unknowns, or its factor
  // rows, for rigid bodies), numbered in the indices' order. Each block's groups, ascending: the indices
  // that some column of the block reaches are those of its groups, whole.
  std::span<const int> groups_of(int block) const {
    return {block_groups_.data() + block_group_start_[block],
            static_cast<std::size_t>(block_group_start_[block + 1] - block_group_start_[block])};
  }
  int group_first(int group) const { return group_first_[group]; }
  int group_size(int group) const { return group_end_[group] - group_first_[group]; }

  // W (columns square) on this pattern, by blocks: block(p, q, out) for each pair p ≤ q of blocks that
  // share an index writes W's block (p, q), width(p) × width(q), into out by rows (out[r·width(q) + s] =
  // W(first_column(p) + r, first_column(q) + s)); for p = q only its upper triangle (s ≥ r) is read. The
  // rest is mirrored.
  template <class Block>
  void fill_blocks(Eigen::SparseMatrix<double, Eigen::RowMajor>& W, Block&& block) const;
  // The same by entries: W_ab = entry(a, b) for a ≤ b, mirrored below.
  template <class Entry>
  void fill(Eigen::SparseMatrix<double, Eigen::RowMajor>& W, Entry&& entry) const {
    fill_blocks(W, [&](int p, int q, double* out) {
      const int a0 = first_column(p), b0 = first_column(q), wq = width(q);
      for (int r = 0; r < width(p); ++r)
        for (int s = p == q ? r : 0; s < wq; ++s) out[r * wq + s] = entry(a0 + r, b0 + s);
    });
  }

 private:
  int block_of(int a) const { return a < contact_columns_ ? a / dimension_ : contacts_ + (a - contact_columns_); }
  std::span<const int> group_blocks(int group) const {  // the blocks reaching the group, ascending
    const int i = group_first_[group];
    return {index_blocks_.data() + index_block_start_[i],
            static_cast<std::size_t>(index_block_start_[i + 1] - index_block_start_[i])};
  }
  std::span<const int> neighbours(int block) const {
    return {neighbour_list_.data() + neighbour_start_[block],
            static_cast<std::size_t>(neighbour_start_[block + 1] - neighbour_start_[block])};
  }

  // Block out (P × Q, by rows) into W's values: at `block` (its first entry; rows `length` apart) and
  // transposed at `mirror` (rows `mirror_length` apart); a diagonal block from its upper triangle.
  template <int P, int Q>
  static void place(const double* out, bool diagonal, double* block, int length, double* mirror, int mirror_length) {
    for (int r = 0; r < P; ++r)
      for (int s = 0; s < Q; ++s)
        if (!diagonal || s >= r) {
          block[r * length + s] = out[r * Q + s];
          mirror[s * mirror_length + r] = out[r * Q + s];
        }
  }

  int columns_ = 0, dimension_ = 3, contacts_ = 0, contact_columns_ = 0, blocks_ = 0;
  long nonzeros_ = 0;
  // Compressed lists: each index's blocks (ascending), each block's groups (ascending), each block's
  // neighbours (the blocks sharing an index with it, itself included, ascending); the groups' indices.
  std::vector<int> index_block_start_, index_blocks_;
  std::vector<int> block_group_start_, block_groups_;
  std::vector<int> neighbour_start_, neighbour_list_;  // neighbour_list_ may be longer than its lists
  std::vector<int> group_first_, group_end_;
  std::vector<int> last_block_, cursor_;  // work space
  mutable std::vector<int> mirror_offset_;  // fill's work space
};

template <class Block>
void BlockPattern::fill_blocks(Eigen::SparseMatrix<double, Eigen::RowMajor>& W, Block&& block) const {
  W.resize(columns_, columns_);
  W.resizeNonZeros(static_cast<Eigen::Index>(nonzeros_));
  int* start = W.outerIndexPtr();
  int* column = W.innerIndexPtr();
  double* value = W.valuePtr();
  // The pattern's sizes as locals: the stores into W's int arrays would otherwise reload the members.
  const int blocks = blocks_, contacts = contacts_, dimension = dimension_, contact_columns = contact_columns_;
  const auto first = [=](int b) { return b < contacts ? dimension * b : contact_columns + (b - contacts); };
  const auto wide = [=](int b) { return b < contacts ? dimension : 1; };
  // The structure: a row of block p holds its neighbours' columns in order, the same for each of its rows.
  int next = 0;
  for (int p = 0; p < blocks; ++p) {
    const int a0 = first(p), row_start = next;
    start[a0] = next;
    for (const int q : neighbours(p))
      for (int s = 0, b0 = first(q), wq = wide(q); s < wq; ++s) column[next++] = b0 + s;
    const int length = next - row_start;
    for (int r = 1; r < wide(p); ++r) {
      start[a0 + r] = next;
      std::copy(column + row_start, column + row_start + length, column + next);
      next += length;
    }
  }
  start[columns_] = next;
  // The values: block (p, q), p ≤ q, at column offset `offset` of p's rows, and its transpose at the
  // offset of p in q's rows. The blocks p' ≤ q of q's (ascending) neighbours are met in ascending p', so
  // that this offset is the widths of those met before.
  mirror_offset_.assign(blocks, 0);
  double out[kMaxWidth * kMaxWidth] = {};
  for (int p = 0; p < blocks; ++p) {
    const int wp = wide(p);
    double* const row = value + start[first(p)];   // p's rows, each `length` long
    const int length = wp > 1 ? start[first(p) + 1] - start[first(p)] : 0;
    int offset = 0;
    for (const int q : neighbours(p)) {
      const int wq = wide(q);
      if (q >= p) {
        block(p, q, out);
        double* const mirror = value + start[first(q)] + mirror_offset_[q];  // q's rows, at p's columns
        const int mirror_length = wq > 1 ? start[first(q) + 1] - start[first(q)] : 0;
        mirror_offset_[q] += wp;
        switch (wp * (kMaxWidth + 1) + wq) {  // the widths as constants: the loops unrolled
          case 3 * (kMaxWidth + 1) + 3: place<3, 3>(out, p == q, row + offset, length, mirror, mirror_length); break;
          case 3 * (kMaxWidth + 1) + 1: place<3, 1>(out, false, row + offset, length, mirror, mirror_length); break;
          case 1 * (kMaxWidth + 1) + 3: place<1, 3>(out, false, row + offset, length, mirror, mirror_length); break;
          case 2 * (kMaxWidth + 1) + 2: place<2, 2>(out, p == q, row + offset, length, mirror, mirror_length); break;
          case 2 * (kMaxWidth + 1) + 1: place<2, 1>(out, false, row + offset, length, mirror, mirror_length); break;
          case 1 * (kMaxWidth + 1) + 2: place<1, 2>(out, false, row + offset, length, mirror, mirror_length); break;
          case 1 * (kMaxWidth + 1) + 1: place<1, 1>(out, false, row + offset, length, mirror, mirror_length); break;
          default:  // widths 1 and 2 with 3 are not in one pattern
            for (int r = 0; r < wp; ++r)
              for (int s = p == q ? r : 0; s < wq; ++s)
                row[r * length + offset + s] = mirror[s * mirror_length + r] = out[r * wq + s];
        }
      }
      offset += wq;
    }
  }
}

}  // namespace csim
