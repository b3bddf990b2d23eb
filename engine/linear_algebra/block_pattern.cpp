#include "engine/linear_algebra/block_pattern.h"

#include <algorithm>

namespace csim {

bool BlockPattern::build(int size, const std::vector<const std::vector<int>*>& reach, int dimension, int contacts,
                         double max_density) {
  const int m = static_cast<int>(reach.size());
  columns_ = m;
  dimension_ = dimension;
  contacts_ = contacts;
  contact_columns_ = dimension * contacts;
  blocks_ = contacts + (m - contact_columns_);
  neighbours_.clear();
  nonzeros_ = 0;

  // How many blocks reach each index (a block's columns are consecutive: last_block dedups them).
  if (max_density < 1.0) {
    const double limit = max_density * blocks_;
    count_.assign(size, 0);
    last_block_.assign(size, -1);
    for (int a = 0; a < m; ++a)
      for (const int index : *reach[a])
        if (last_block_[index] != block_of(a)) {
          last_block_[index] = block_of(a);
          if (++count_[index] > limit) return false;
        }
  }

  // Each index reached, with the blocks reaching it (each block once per index).
  reached_.clear();
  for (int a = 0; a < m; ++a)
    for (const int index : *reach[a]) reached_.emplace_back(index, block_of(a));
  std::sort(reached_.begin(), reached_.end());
  reached_.erase(std::unique(reached_.begin(), reached_.end()), reached_.end());

  // The blocks each block shares an index with (itself included), ascending.
  neighbours_.resize(blocks_);
  for (std::size_t first = 0; first < reached_.size();) {
    std::size_t last = first;
    while (last < reached_.size() && reached_[last].first == reached_[first].first) ++last;
    for (std::size_t p = first; p < last; ++p)
      for (std::size_t q = first; q < last; ++q) neighbours_[reached_[p].second].push_back(reached_[q].second);
    first = last;
  }
  for (std::vector<int>& list : neighbours_) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  for (int block = 0; block < blocks_; ++block) {
    long row_entries = 0;
    for (const int other : neighbours_[block]) row_entries += width(other);
    nonzeros_ += row_entries * width(block);
  }
  return true;
}

}  // namespace csim
