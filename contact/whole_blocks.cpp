#include "contact/whole_blocks.h"

#include <algorithm>
#include <cstdint>

namespace csim {

SparseDelassus whole_blocks(int size, int dimension, const std::vector<Eigen::Triplet<double>>& entries) {
  const std::int64_t block_count = size / dimension;
  std::vector<std::int64_t> blocks;
  blocks.reserve(entries.size());
  for (const Eigen::Triplet<double>& entry : entries)
    blocks.push_back(entry.row() / dimension * block_count + entry.col() / dimension);
  std::sort(blocks.begin(), blocks.end());
  blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(blocks.size() * dimension * dimension + entries.size());
  for (const std::int64_t block : blocks) {
    const int row = static_cast<int>(block / block_count) * dimension;
    const int column = static_cast<int>(block % block_count) * dimension;
    for (int i = 0; i < dimension; ++i)
      for (int j = 0; j < dimension; ++j) triplets.emplace_back(row + i, column + j, 0.0);
  }
  triplets.insert(triplets.end(), entries.begin(), entries.end());
  SparseDelassus W(size, size);
  W.setFromTriplets(triplets.begin(), triplets.end());
  return W;
}

}  // namespace csim
