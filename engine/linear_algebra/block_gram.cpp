#include "engine/linear_algebra/block_gram.h"

namespace csim {

namespace {

// out (P × Q, by rows) += the products of `rows` rows of panels a (P wide) and b (Q wide), at factor
// rows of pivots D: out_rs += a_kr b_ks / D_k, k ascending (see the header).
template <int P, int Q>
void add_products(const double* a, const double* b, const double* pivots, int rows, double* out) {
  double sum[P * Q];
  for (int e = 0; e < P * Q; ++e) sum[e] = out[e];
  for (int k = 0; k < rows; ++k)
    for (int r = 0; r < P; ++r)
      for (int s = 0; s < Q; ++s) sum[r * Q + s] += a[k * P + r] * b[k * Q + s] / pivots[k];
  for (int e = 0; e < P * Q; ++e) out[e] = sum[e];
}

// Block (p, q) of W into out (P × Q, by rows): the groups both blocks reach, merged from their ascending
// lists (each group's rows at a running offset in each panel), each added whole.
template <int P, int Q>
void panel_product(const BlockPattern& pattern, int p, int q, const double* a, const double* b,
                   const double* pivots, double* out) {
  for (int e = 0; e < P * Q; ++e) out[e] = 0.0;
  const std::span<const int> a_groups = pattern.groups_of(p), b_groups = pattern.groups_of(q);
  std::size_t k = 0, l = 0;
  while (k < a_groups.size() && l < b_groups.size()) {
    const int g = a_groups[k], h = b_groups[l];
    if (g < h) {
      a += P * pattern.group_size(g);
      ++k;
    } else if (h < g) {
      b += Q * pattern.group_size(h);
      ++l;
    } else {
      const int rows = pattern.group_size(g);
      add_products<P, Q>(a, b, pivots + pattern.group_first(g), rows, out);
      a += P * rows;
      b += Q * rows;
      ++k;
      ++l;
    }
  }
}

template <int P>
void panel_product_by(int q_width, const BlockPattern& pattern, int p, int q, const double* a, const double* b,
                      const double* pivots, double* out) {
  if (q_width == 3) panel_product<P, 3>(pattern, p, q, a, b, pivots, out);
  else if (q_width == 2) panel_product<P, 2>(pattern, p, q, a, b, pivots, out);
  else panel_product<P, 1>(pattern, p, q, a, b, pivots, out);
}

}  // namespace

bool BlockGram::assemble(const SparseLdlt& factor, const std::vector<const SparseLdlt::ForwardColumn*>& columns,
                         int dimension, int contacts, Eigen::SparseMatrix<double, Eigen::RowMajor>& W,
                         double max_density) {
  reach_.resize(columns.size());
  for (std::size_t a = 0; a < columns.size(); ++a) reach_[a] = &columns[a]->index;
  if (!pattern_.build(factor.size(), reach_, dimension, contacts, max_density)) return false;

  // The panels: row k of block p's holds its columns' values at its k-th factor row (its groups' rows
  // in order), zero where a column does not reach it.
  const int blocks = pattern_.blocks();
  panel_start_.resize(blocks + 1);
  panel_start_[0] = 0;
  for (int p = 0; p < blocks; ++p) {
    long rows = 0;
    for (const int g : pattern_.groups_of(p)) rows += pattern_.group_size(g);
    panel_start_[p + 1] = panel_start_[p] + rows * pattern_.width(p);
  }
  panels_.resize(panel_start_[blocks]);
  for (int p = 0; p < blocks; ++p) {
    const int width = pattern_.width(p);
    for (int c = 0; c < width; ++c) {
      const SparseLdlt::ForwardColumn& y = *columns[pattern_.first_column(p) + c];
      double* row = panels_.data() + panel_start_[p] + c;
      std::size_t t = 0;  // y's rows are among the block's, both ascending
      for (const int g : pattern_.groups_of(p))
        for (int i = pattern_.group_first(g); i < pattern_.group_first(g) + pattern_.group_size(g); ++i, row += width)
          *row = t < y.index.size() && y.index[t] == i ? y.value[t++] : 0.0;
    }
  }

  const double* pivots = factor.pivots().data();
  pattern_.fill_blocks(W, [&](int p, int q, double* out) {
    const double* a = panels_.data() + panel_start_[p];
    const double* b = panels_.data() + panel_start_[q];
    const int wq = pattern_.width(q);
    switch (pattern_.width(p)) {
      case 3: return panel_product_by<3>(wq, pattern_, p, q, a, b, pivots, out);
      case 2: return panel_product_by<2>(wq, pattern_, p, q, a, b, pivots, out);
      default: return panel_product_by<1>(wq, pattern_, p, q, a, b, pivots, out);
    }
  });
  return true;
}

}  // namespace csim
