#include "engine/linear_algebra/supernodal_ldlt.h"

#include <Eigen/Dense>

#include <algorithm>
#include <stdexcept>

namespace csim {

// The elimination tree by Liu's algorithm with path compression, then the row subtrees of the rows of
// L (Davis, Direct Methods for Sparse Linear Systems, 2006, §4.1–4.2): row k of L has its nonzeros on
// the paths up the tree from the entries M(i, k), i < k, to k. Columns j and j + 1 form one supernode
// when j + 1 is j's parent and column j's pattern is column j + 1's with j: equal below the diagonal
// block. Only each supernode's first column keeps its rows: the other columns' are a tail of them.
void SupernodalLdlt::analyse(int n, const int* upper_start, const int* upper_row) {
  std::vector<int> parent(n, -1), ancestor(n, -1);
  for (int k = 0; k < n; ++k)
    for (int q = upper_start[k]; q < upper_start[k + 1]; ++q)
      for (int i = upper_row[q]; i != -1 && i < k;) {
        const int next = ancestor[i];
        ancestor[i] = k;
        if (next == -1) parent[i] = k;
        i = next;
      }
  std::vector<int> count(n, 1), mark(n, -1);  // entries of each column of L, D included
  for (int k = 0; k < n; ++k) {
    mark[k] = k;
    for (int q = upper_start[k]; q < upper_start[k + 1]; ++q)
      for (int i = upper_row[q]; mark[i] != k; i = parent[i]) {
        mark[i] = k;
        ++count[i];
      }
  }
  first_column_.clear();
  supernode_of_.resize(n);
  for (int j = 0; j < n; ++j) {
    const bool joins = j > 0 && parent[j - 1] == j && count[j - 1] == count[j] + 1;
    if (!joins) first_column_.push_back(j);
    supernode_of_[j] = static_cast<int>(first_column_.size()) - 1;
  }
  first_column_.push_back(n);
  const int supernodes = static_cast<int>(first_column_.size()) - 1;
  row_start_.assign(supernodes + 1, 0);
  for (int s = 0; s < supernodes; ++s) row_start_[s + 1] = row_start_[s] + count[first_column_[s]];
  rows_.resize(row_start_[supernodes]);
  std::vector<int> fill(row_start_.begin(), row_start_.end() - 1);
  std::fill(mark.begin(), mark.end(), -1);
  for (int k = 0; k < n; ++k) {  // rows in ascending order: each list comes out sorted, its diagonal first
    mark[k] = k;
    if (first_column_[supernode_of_[k]] == k) rows_[fill[supernode_of_[k]]++] = k;  // its diagonal
    for (int q = upper_start[k]; q < upper_start[k + 1]; ++q)
      for (int i = upper_row[q]; mark[i] != k; i = parent[i]) {
        mark[i] = k;
        if (first_column_[supernode_of_[i]] == i) rows_[fill[supernode_of_[i]]++] = k;
      }
  }
  for (int s = 0; s < supernodes; ++s)
    if (fill[s] != row_start_[s + 1]) throw std::logic_error("SupernodalLdlt: the row lists do not match the counts");
  // The blocks, and where each entry of triu(M) goes: column i = the entry's row, at its column j's row.
  block_start_.resize(supernodes + 1);
  block_start_[0] = 0;
  int widest = 0, deepest = 0;
  for (int s = 0; s < supernodes; ++s) {
    const int c = row_start_[s + 1] - row_start_[s], w = first_column_[s + 1] - first_column_[s];
    block_start_[s + 1] = block_start_[s] + static_cast<long>(c) * w;
    widest = std::max(widest, c);
    deepest = std::max(deepest, (c - w + 1) * w);
  }
  blocks_.resize(block_start_[supernodes]);
  entry_position_.resize(upper_start[n]);
  for (int j = 0; j < n; ++j)
    for (int q = upper_start[j]; q < upper_start[j + 1]; ++q) {
      const int i = upper_row[q], s = supernode_of_[i];
      const int* first = rows_.data() + row_start_[s];
      const int* last = rows_.data() + row_start_[s + 1];
      const int* found = std::lower_bound(first, last, j);
      if (found == last || *found != j) throw std::logic_error("SupernodalLdlt: an entry of M outside L's pattern");
      entry_position_[q] = block_start_[s] + (found - first) + static_cast<long>(i - first_column_[s]) * (last - first);
    }
  // The update's targets (the structure alone decides them).
  group_start_.assign(1, 0);
  groups_.clear();
  relative_.clear();
  for (int s = 0; s < supernodes; ++s) {
    const int w = first_column_[s + 1] - first_column_[s];
    const int* rows = rows_.data() + row_start_[s];
    const int m = row_start_[s + 1] - row_start_[s] - w;
    for (int a = 0; a < m;) {
      const int J = rows[w + a], t = supernode_of_[J], kt = J - first_column_[t];
      const int* target_rows = rows_.data() + row_start_[t];
      const int ct = row_start_[t + 1] - row_start_[t];
      Group group{a, a, ct, block_start_[t] - static_cast<long>(first_column_[t]) * ct,
                  static_cast<long>(relative_.size())};
      while (group.last < m && rows[w + group.last] < first_column_[t + 1]) ++group.last;
      int position = kt;
      for (int b = a; b < m; ++b) {
        while (target_rows[position] < rows[w + b]) ++position;
        relative_.push_back(position);
      }
      groups_.push_back(group);
      a = group.last;
    }
    group_start_.push_back(static_cast<int>(groups_.size()));
  }
  scaled_.resize(deepest);
  update_.resize(static_cast<std::size_t>(widest) * (widest + 1));
}

void SupernodalLdlt::pattern(std::vector<int>& start, std::vector<int>& row) const {
  start.assign(1, 0);
  row.clear();
  for (int s = 0; s < supernodes(); ++s)
    for (int k = 0; k < first_column_[s + 1] - first_column_[s]; ++k) {
      row.insert(row.end(), rows_.begin() + row_start_[s] + k, rows_.begin() + row_start_[s + 1]);
      start.push_back(static_cast<int>(row.size()));
    }
}

bool SupernodalLdlt::matches(const int* start, const int* count, const int* row) const {
  for (int s = 0; s < supernodes(); ++s) {
    const int* rows = rows_.data() + row_start_[s];
    const int c = row_start_[s + 1] - row_start_[s];
    for (int j = first_column_[s]; j < first_column_[s + 1]; ++j) {
      const int k = j - first_column_[s];
      if (count[j] != c - k || !std::equal(rows + k, rows + c, row + start[j])) return false;
    }
  }
  return true;
}

namespace {

using Block42 = Eigen::Matrix<double, 4, 2>;

// acc += P(4 rows, K columns) S(2 rows, K columns)ᵀ, P and S by columns with strides ldp and lds:
// fixed sizes, which Eigen unrolls and vectorizes over P's rows.
template <int K>
void add_product(const double* P, int ldp, const double* S, int lds, Block42& acc) {
  using Lhs = Eigen::Map<const Eigen::Matrix<double, 4, K>, Eigen::Unaligned, Eigen::OuterStride<>>;
  using Rhs = Eigen::Map<const Eigen::Matrix<double, 2, K>, Eigen::Unaligned, Eigen::OuterStride<>>;
  acc.noalias() += Lhs(P, Eigen::OuterStride<>(ldp)).lazyProduct(Rhs(S, Eigen::OuterStride<>(lds)).transpose());
}

// U(b, a) = Σ_k P(b, k) S(a, k) for b ≥ a, two columns a, a + 1 and four rows at a time (the strict
// upper entries that fall in such a block are written too, and not read); U by columns with stride m.
// P is m × w with stride ldp; S is (m + 1) × w with stride m + 1, its last row zero, so that an odd
// m's last pair reads it and writes U's column m (U has m + 1 columns). A general matrix product
// does not pay for its packing on blocks this small (docs/rolling.md).
void lower_product(int m, int w, const double* P, int ldp, const double* S, double* U) {
  const int lds = m + 1;
  for (int a = 0; a < m; a += 2) {
    // Blocks of four rows ending at row m − 1, the first reaching up past a when m − a is not a multiple
    // of four (entries above the diagonal, not read), so that no row is left for a scalar loop; rows
    // from a when m is under four.
    int b = m - 4 * ((m - a + 3) / 4);
    if (b < 0) b = a;
    for (; b + 4 <= m; b += 4) {
      Block42 acc = Block42::Zero();
      int k = 0;
      for (; k + 4 <= w; k += 4) add_product<4>(P + static_cast<long>(k) * ldp + b, ldp, S + static_cast<long>(k) * lds + a, lds, acc);
      const double* p = P + static_cast<long>(k) * ldp + b;
      const double* s = S + static_cast<long>(k) * lds + a;
      switch (w - k) {
        case 3: add_product<3>(p, ldp, s, lds, acc); break;
        case 2: add_product<2>(p, ldp, s, lds, acc); break;
        case 1: add_product<1>(p, ldp, s, lds, acc); break;
        default: break;
      }
      Eigen::Map<Eigen::Matrix<double, 4, 2>, Eigen::Unaligned, Eigen::OuterStride<>>(U + static_cast<long>(a) * m + b,
                                                                                      Eigen::OuterStride<>(m)) = acc;
    }
    for (; b < m; ++b) {
      double c0 = 0.0, c1 = 0.0;
      for (int k = 0; k < w; ++k) {
        const double p = P[static_cast<long>(k) * ldp + b];
        c0 += p * S[static_cast<long>(k) * lds + a];
        c1 += p * S[static_cast<long>(k) * lds + a + 1];
      }
      U[static_cast<long>(a) * m + b] = c0;
      U[static_cast<long>(a + 1) * m + b] = c1;
    }
  }
}

// target[position[i]] −= value[i] for i < count: distinct positions, so that the four of a group do
// not depend on each other (restrict tells the compiler so).
void subtract_at(int count, const double* __restrict value, const int* __restrict position, double* __restrict target) {
  int i = 0;
  for (; i + 4 <= count; i += 4) {
    target[position[i]] -= value[i];
    target[position[i + 1]] -= value[i + 1];
    target[position[i + 2]] -= value[i + 2];
    target[position[i + 3]] -= value[i + 3];
  }
  for (; i < count; ++i) target[position[i]] -= value[i];
}

}  // namespace

bool SupernodalLdlt::factor(const double* upper_value, const int* start, double* x) {
  using Block = Eigen::Map<Eigen::MatrixXd>;
  const int supernodes = this->supernodes();
  std::fill(blocks_.begin(), blocks_.end(), 0.0);
  for (std::size_t q = 0; q < entry_position_.size(); ++q) blocks_[entry_position_[q]] = upper_value[q];
  for (int s = 0; s < supernodes; ++s) {
    const int w = first_column_[s + 1] - first_column_[s];
    const int* rows = rows_.data() + row_start_[s];
    const int c = row_start_[s + 1] - row_start_[s], m = c - w;
    Block B(blocks_.data() + block_start_[s], c, w);
    // The supernode's own columns, left-looking within it: the earlier supernodes' contributions are in.
    for (int k = 0; k < w; ++k) {
      for (int j = 0; j < k; ++j) B.col(k).tail(c - k) -= B.col(j).tail(c - k) * (B(k, j) * B(j, j));
      const double pivot = B(k, k);
      if (!(pivot > 0.0)) return false;
      B.col(k).tail(c - k - 1) /= pivot;
    }
    if (m == 0) continue;
    // Its contribution U = L_s D_s L_sᵀ below the diagonal block (lower triangle), subtracted from each
    // later column J = rows[w + a] at the positions of its rows in J's supernode: a tail of that
    // supernode's rows, the same positions for every column aiming at it (found once).
    Block scaled(scaled_.data(), m + 1, w);
    scaled.topRows(m).noalias() = B.bottomRows(m) * B.topRows(w).diagonal().asDiagonal();
    scaled.row(m).setZero();
    lower_product(m, w, B.data() + w, c, scaled.data(), update_.data());
    for (int g = group_start_[s]; g < group_start_[s + 1]; ++g) {
      const Group& group = groups_[g];
      const int* relative = relative_.data() + group.at - group.first;  // relative[b], b ≥ group.first
      for (int a = group.first; a < group.last; ++a) {
        double* target_column = blocks_.data() + (group.origin + static_cast<long>(rows[w + a]) * group.rows);
        const double* u = update_.data() + static_cast<long>(a) * m;
        subtract_at(m - a, u + a, relative + a, target_column);
      }
    }
  }
  // Out to the simplicial storage: column j of L from its diagonal down.
  for (int s = 0; s < supernodes; ++s) {
    const int c = row_start_[s + 1] - row_start_[s];
    const double* block = blocks_.data() + block_start_[s];
    for (int k = 0; k < first_column_[s + 1] - first_column_[s]; ++k)
      std::copy_n(block + static_cast<long>(k) * c + k, c - k, x + start[first_column_[s] + k]);
  }
  return true;
}

}  // namespace csim
