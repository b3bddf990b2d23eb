#include "engine/linear_algebra/block_pattern.h"

#include <algorithm>
#include <stdexcept>

namespace csim {

bool BlockPattern::build(int size, const std::vector<const std::vector<int>*>& reach, int dimension, int contacts,
                         double max_density) {
  if (dimension < 1 || dimension > kMaxWidth) throw std::invalid_argument("BlockPattern: dimension not in [1, 3]");
  const int m = static_cast<int>(reach.size());
  columns_ = m;
  dimension_ = dimension;
  contacts_ = contacts;
  contact_columns_ = dimension * contacts;
  blocks_ = contacts + (m - contact_columns_);
  nonzeros_ = 0;
  neighbour_start_.assign(blocks_ + 1, 0);
  group_first_.clear();
  group_end_.clear();

  // Calls visit(index, block) once for each index a block reaches, blocks in column order (a block's
  // columns are consecutive: last_block_ drops the repeats); stops at the first visit that returns false.
  const auto each_reached = [&](auto&& visit) {
    last_block_.assign(size, -1);
    for (int a = 0; a < m; ++a) {
      const int block = block_of(a);
      for (const int index : *reach[a])
        if (last_block_[index] != block) {
          last_block_[index] = block;
          if (!visit(index, block)) return false;
        }
    }
    return true;
  };

  // How many blocks reach each index, with the density test.
  const double limit = max_density * blocks_;
  index_block_start_.assign(size + 1, 0);
  if (!each_reached([&](int index, int) { return ++index_block_start_[index + 1] <= limit; })) {
    neighbour_start_.assign(blocks_ + 1, 0);
    return false;
  }
  for (int i = 0; i < size; ++i) index_block_start_[i + 1] += index_block_start_[i];

  // Each index's blocks, ascending (the columns in order): a counting sort.
  index_blocks_.resize(index_block_start_[size]);
  cursor_.assign(index_block_start_.begin(), index_block_start_.end() - 1);
  each_reached([&](int index, int block) {
    index_blocks_[cursor_[index]++] = block;
    return true;
  });

  // The groups: runs of consecutive indices reached by the same blocks.
  const auto blocks_at = [&](int i) {
    return std::span<const int>(index_blocks_.data() + index_block_start_[i],
                                static_cast<std::size_t>(index_block_start_[i + 1] - index_block_start_[i]));
  };
  for (int i = 0; i < size; ++i) {
    if (blocks_at(i).empty()) continue;
    if (!group_end_.empty() && group_end_.back() == i && std::ranges::equal(blocks_at(i), blocks_at(i - 1))) {
      ++group_end_.back();
    } else {
      group_first_.push_back(i);
      group_end_.push_back(i + 1);
    }
  }
  const int groups = static_cast<int>(group_first_.size());

  // Each block's groups, ascending: a counting sort.
  block_group_start_.assign(blocks_ + 1, 0);
  for (int g = 0; g < groups; ++g)
    for (const int p : group_blocks(g)) ++block_group_start_[p + 1];
  for (int p = 0; p < blocks_; ++p) block_group_start_[p + 1] += block_group_start_[p];
  block_groups_.resize(block_group_start_[blocks_]);
  cursor_.assign(block_group_start_.begin(), block_group_start_.end() - 1);
  for (int g = 0; g < groups; ++g)
    for (const int p : group_blocks(g)) block_groups_[cursor_[p]++] = g;

  // The blocks each block shares an index with (itself included), ascending: the union of its groups'
  // lists, merged when there are two (a contact between two bodies), else marked (last_block_ by block)
  // and sorted. Written through a pointer into room for their bound Σ_p Σ_{g ∈ p} |blocks of g| (a
  // push_back would reload every vector's members after each store), kept from one call to the next.
  long bound = 0;
  for (const int g : block_groups_) bound += static_cast<long>(group_blocks(g).size());
  if (static_cast<long>(neighbour_list_.size()) < bound) neighbour_list_.resize(bound);
  last_block_.assign(blocks_, -1);
  int* mark = last_block_.data();
  int* list = neighbour_list_.data();
  int next = 0;
  for (int p = 0; p < blocks_; ++p) {
    const std::span<const int> own = groups_of(p);
    if (own.size() == 1) {
      next = static_cast<int>(std::ranges::copy(group_blocks(own[0]), list + next).out - list);
    } else if (own.size() == 2) {
      next = static_cast<int>(std::ranges::set_union(group_blocks(own[0]), group_blocks(own[1]), list + next).out - list);
    } else {
      const int row_start = next;
      for (const int g : own)
        for (const int q : group_blocks(g))
          if (mark[q] != p) {
            mark[q] = p;
            list[next++] = q;
          }
      std::sort(list + row_start, list + next);
    }
    long row_entries = 0;
    for (int k = neighbour_start_[p]; k < next; ++k) row_entries += width(list[k]);
    neighbour_start_[p + 1] = next;
    nonzeros_ += row_entries * width(p);
  }
  return true;
}

}  // namespace csim
