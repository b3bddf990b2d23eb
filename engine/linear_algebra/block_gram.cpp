#include "engine/linear_algebra/block_gram.h"

#include <algorithm>

namespace csim {

bool block_gram(const SparseLdlt& factor, const std::vector<const SparseLdlt::ForwardColumn*>& columns,
                int dimension, int contacts, Eigen::SparseMatrix<double, Eigen::RowMajor>& W,
                double max_density) {
  const int m = static_cast<int>(columns.size());
  const int contact_columns = dimension * contacts;
  const int blocks = contacts + (m - contact_columns);
  auto block_of = [&](int a) { return a < contact_columns ? a / dimension : contacts + (a - contact_columns); };
  auto first_column = [&](int block) {
    return block < contacts ? dimension * block : contact_columns + (block - contacts);
  };
  auto width = [&](int block) { return block < contacts ? dimension : 1; };

  // How many blocks reach each factor row (a block's columns are consecutive: last_block dedups them).
  if (max_density < 1.0) {
    const double limit = max_density * blocks;
    std::vector<int> count(factor.size(), 0), last_block(factor.size(), -1);
    for (int a = 0; a < m; ++a)
      for (const int row : columns[a]->index)
        if (last_block[row] != block_of(a)) {
          last_block[row] = block_of(a);
          if (++count[row] > limit) return false;
        }
  }

  // Each factor row reached, with the blocks reaching it (each block once per row).
  std::vector<std::pair<int, int>> reached;  // (factor row, block)
  for (int a = 0; a < m; ++a)
    for (const int row : columns[a]->index) reached.emplace_back(row, block_of(a));
  std::sort(reached.begin(), reached.end());
  reached.erase(std::unique(reached.begin(), reached.end()), reached.end());

  // The blocks each block shares a factor row with (itself included), ascending.
  std::vector<std::vector<int>> neighbours(blocks);
  for (std::size_t first = 0; first < reached.size();) {
    std::size_t last = first;
    while (last < reached.size() && reached[last].first == reached[first].first) ++last;
    for (std::size_t p = first; p < last; ++p)
      for (std::size_t q = first; q < last; ++q) neighbours[reached[p].second].push_back(reached[q].second);
    first = last;
  }
  for (std::vector<int>& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }

  // Row by row in order, columns ascending: the compressed storage filled directly. An entry of the
  // upper triangle is computed, one of the lower triangle read from its mirror (already stored).
  W.resize(m, m);
  long nonzeros = 0;
  for (int block = 0; block < blocks; ++block) {
    long row_entries = 0;
    for (const int other : neighbours[block]) row_entries += width(other);
    nonzeros += row_entries * width(block);
  }
  W.reserve(nonzeros);
  for (int block = 0; block < blocks; ++block)
    for (int a = first_column(block); a < first_column(block) + width(block); ++a) {
      W.startVec(a);
      for (const int other : neighbours[block])
        for (int b = first_column(other); b < first_column(other) + width(other); ++b)
          W.insertBack(a, b) = b < a ? W.coeff(b, a) : factor.delassus_entry(*columns[a], *columns[b]);
    }
  W.finalize();
  return true;
}

}  // namespace csim
