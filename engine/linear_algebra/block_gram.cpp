#include "engine/linear_algebra/block_gram.h"

#include "engine/linear_algebra/block_pattern.h"

namespace csim {

bool block_gram(const SparseLdlt& factor, const std::vector<const SparseLdlt::ForwardColumn*>& columns,
                int dimension, int contacts, Eigen::SparseMatrix<double, Eigen::RowMajor>& W,
                double max_density) {
  std::vector<const std::vector<int>*> reach(columns.size());
  for (std::size_t a = 0; a < columns.size(); ++a) reach[a] = &columns[a]->index;
  BlockPattern pattern;
  if (!pattern.build(factor.size(), reach, dimension, contacts, max_density)) return false;
  pattern.fill(W, [&](int a, int b) { return factor.delassus_entry(*columns[a], *columns[b]); });
  return true;
}

}  // namespace csim
