// SparseLdlt (sparse_ldlt.h): the symbolic analysis of a pattern (the ordering P and the map of A's
// lower triangle into triu(P A Pᵀ)), the factorization (CHOLMOD's, or the supernodal refactorization
// into its storage) and what it says of A: positive definite or not, its small pivots.
#include "engine/linear_algebra/sparse_ldlt_storage.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace csim {

SparseLdlt::SparseLdlt() : cholmod_(std::make_unique<Cholmod>()) {}
SparseLdlt::SparseLdlt(Kernels kernels) : SparseLdlt() {
  kernels_ = kernels;
}
SparseLdlt::~SparseLdlt() = default;

void SparseLdlt::release_pattern() {
  Cholmod& c = *cholmod_;
  std::vector<int>().swap(outer_);  // an empty pattern matches no matrix: the next factorization analyses
  std::vector<int>().swap(inner_);
  std::vector<int>().swap(c.upper_start);
  std::vector<int>().swap(c.upper_row);
  std::vector<int>().swap(c.slot);
  std::vector<double>().swap(c.upper_value);
  supernodal_ = SupernodalLdlt();  // the blocks go with the pattern; the factor stays CHOLMOD's storage
  supernodal_ready_ = false;
}

int SparseLdlt::size() const { return cholmod_->factor ? static_cast<int>(cholmod_->factor->n) : 0; }

double SparseLdlt::factor_nonzeros() const {
  if (!cholmod_->factor) return 0.0;
  if (!ours_) return cholmod_->analysed_nonzeros;
  const int n = size();
  double count = 0.0;
  for (int j = 0; j < n; ++j) count += cholmod_->column_count()[j];
  return count;
}

// The ordering once per pattern: of CHOLMOD's AMD and METIS' nested dissection on A's lower triangle,
// each followed by its postorder of the elimination tree, the one whose factor costs fewer flops (AMD
// when both cost the same, or when METIS is not there). Neither wins everywhere: on a rolling ring's
// tangent METIS needs a fifth fewer flops, on its frictionless press a tenth more (docs/rolling.md).
// The factor itself is analysed, with the natural ordering, for triu(P A Pᵀ), whose entries are A's at
// a map kept here: CHOLMOD then factors the matrix it is handed as it is, where with its own P it would
// make P A Pᵀ by a transpose at every factorization. The factor and its arithmetic are those of
// CHOLMOD's own permutation, which forms the same triu(P A Pᵀ).
void SparseLdlt::analyse(const SparseMatrix& A) {
  Cholmod& c = *cholmod_;
  const int n = static_cast<int>(A.outerSize()), nnz = static_cast<int>(A.nonZeros());
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  if (c.factor) cholmod_free_factor(&c.factor, &c.common);
  c.choose_ordering(n, outer, inner, A.valuePtr());
  c.map_to_permuted_upper(n, nnz, outer, inner);
  c.common.method[0].ordering = CHOLMOD_NATURAL;
  c.common.postorder = 0;  // P is already postordered; the factor's order must stay triu(P A Pᵀ)'s
  cholmod_sparse upper = view_triangle(n, c.upper_start.data(), c.upper_row.data(), c.upper_value.data(), 1);
  c.factor = cholmod_analyze(&upper, &c.common);
  if (!c.factor) throw std::runtime_error("CHOLMOD could not analyse the matrix (out of memory?)");
  if (c.factor->ordering != CHOLMOD_NATURAL) throw std::logic_error("SparseLdlt: CHOLMOD reordered a permuted matrix");
  c.analysed_nonzeros = c.common.lnz;
  outer_.assign(outer, outer + n + 1);
  inner_.assign(inner, inner + nnz);
  ++analyses_;
  cholmod_complete_ = supernodal_ready_ = sweeps_ready_ = ours_ = false;
}

void SparseLdlt::Cholmod::choose_ordering(int n, const int* outer, const int* inner, const double* value) {
  common.postorder = 1;
  cholmod_sparse lower = view_triangle(n, outer, inner, value, -1);
  double fewest = std::numeric_limits<double>::infinity();
  for (const int method : {CHOLMOD_AMD, CHOLMOD_METIS}) {
    common.method[0].ordering = method;
    cholmod_factor* ordering = cholmod_analyze(&lower, &common);
    if (!ordering) {
      if (method == CHOLMOD_AMD) throw std::runtime_error("CHOLMOD could not analyse the matrix (out of memory?)");
      continue;  // METIS is optional
    }
    if (common.fl < fewest) {
      fewest = common.fl;
      const int* order = static_cast<const int*>(ordering->Perm);
      permutation.assign(order, order + n);
    }
    cholmod_free_factor(&ordering, &common);
  }
  inverse.resize(n);
  for (int k = 0; k < n; ++k) inverse[permutation[k]] = k;
}

// A's entry (i, j), i ≥ j, goes to (min, max) of (P i, P j), in the order CHOLMOD's permuted transpose
// (cholmod_transpose_sym) lays them: the columns of P A Pᵀ in turn, each entry appended to its column
// of the upper triangle. The simplicial factorization's sums follow the order of a column's entries,
// so that this order, not only the values, gives CHOLMOD's factor bit for bit.
void SparseLdlt::Cholmod::map_to_permuted_upper(int n, int nnz, const int* outer, const int* inner) {
  upper_start.assign(n + 1, 0);
  for (int j = 0; j < n; ++j) {
    const int old = permutation[j];
    for (int p = outer[old]; p < outer[old + 1]; ++p)
      if (inner[p] >= old) ++upper_start[std::max(inverse[inner[p]], j) + 1];
  }
  for (int j = 0; j < n; ++j) upper_start[j + 1] += upper_start[j];
  std::vector<int> fill(upper_start.begin(), upper_start.end() - 1);
  upper_row.resize(upper_start[n]);
  upper_value.assign(upper_start[n], 0.0);
  slot.assign(nnz, -1);  // above the diagonal: CHOLMOD reads the lower triangle only
  for (int j = 0; j < n; ++j) {
    const int old = permutation[j];
    for (int p = outer[old]; p < outer[old + 1]; ++p) {
      if (inner[p] < old) continue;
      const int i = inverse[inner[p]];
      const int position = fill[std::max(i, j)]++;
      upper_row[position] = std::min(i, j);
      slot[p] = position;
    }
  }
}

bool SparseLdlt::factor_positive_definite(const SparseMatrix& A) {
  if (!A.isCompressed()) {  // a coeffRef that inserted an entry
    SparseMatrix compressed = A;
    compressed.makeCompressed();
    return factor_positive_definite(compressed);
  }
  Cholmod& c = *cholmod_;
  const int n = static_cast<int>(A.outerSize()), nnz = static_cast<int>(A.nonZeros());
  const bool same = c.factor && static_cast<int>(outer_.size()) == n + 1 && static_cast<int>(inner_.size()) == nnz &&
                    std::equal(outer_.begin(), outer_.end(), A.outerIndexPtr()) &&
                    std::equal(inner_.begin(), inner_.end(), A.innerIndexPtr());
  if (!same) analyse(A);
  const double* value = A.valuePtr();
  for (int p = 0; p < nnz; ++p)
    if (c.slot[p] >= 0) c.upper_value[c.slot[p]] = value[p];
  ++factorizations_;
  tree_ready_ = false;
  // A refactorization: supernodal, once CHOLMOD's storage is known to hold the pattern (see the header).
  if (cholmod_complete_ && !supernodal_ready_) {
    supernodal_.analyse(n, c.upper_start.data(), c.upper_row.data());
    supernodal_ready_ = supernodal_.matches(c.column_start(), c.column_count(), c.row_index());
  }
  if (supernodal_ready_) {
    ++supernodal_factorizations_;
    if (supernodal_.factor(c.upper_value.data(), c.column_start(), c.values())) return true;
  }
  cholmod_sparse upper = view_triangle(n, c.upper_start.data(), c.upper_row.data(), c.upper_value.data(), 1);
  double no_shift[2] = {0.0, 0.0};
  cholmod_factorize_p(&upper, no_shift, nullptr, 0, c.factor, &c.common);
  sweeps_ready_ = false;
  if (c.common.status < CHOLMOD_OK) throw std::runtime_error("CHOLMOD could not factor the matrix (out of memory?)");
  if (kernels_ == Kernels::cholmod_ll && !c.factor->is_ll && c.factor->minor == c.factor->n &&
      !cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, c.factor, &c.common))
    throw std::runtime_error("CHOLMOD could not convert the factor (out of memory?)");
  // The layout, checked once per CHOLMOD factorization: our kernels read this factor, or CHOLMOD does.
  ours_ = kernels_ == Kernels::ours_where_supported && cholmod_layout_supported(*c.factor);
  const bool complete = c.factor->minor == c.factor->n;
  cholmod_complete_ = ours_ && complete;
  if (!cholmod_complete_) supernodal_ready_ = false;  // its storage may no longer hold every column
  if (!complete) return false;  // a zero pivot (an LLᵀ factor: a pivot not > 0)
  if (!ours_) {
    if (c.factor->is_ll) return true;  // complete: every pivot was > 0
    prepare_tree();
    return (pivots_.array() > 0.0).all();
  }
  const int* start = c.column_start();
  const double* x = c.values();
  for (int j = 0; j < n; ++j)
    if (!(x[start[j]] > 0.0)) return false;  // D_j, first in column j of L
  return true;
}

std::vector<int> SparseLdlt::small_pivots(const Vector& diagonal, double tolerance) const {
  const Cholmod& c = *cholmod_;
  std::vector<int> small;
  if (!c.factor) return small;
  const int n = static_cast<int>(c.factor->n);
  if (static_cast<int>(c.factor->minor) < n) {  // stopped at a zero pivot
    small.push_back(c.permutation[c.factor->minor]);
    return small;
  }
  Vector D(n);
  if (ours_) {
    for (int j = 0; j < n; ++j) D(j) = c.values()[c.column_start()[j]];
  } else {
    cholmod_pivots(D, true);
  }
  for (int j = 0; j < n; ++j) {
    const int unknown = c.permutation[j];
    if (!(D(j) > tolerance * std::max(diagonal(unknown), 0.0))) small.push_back(unknown);
  }
  std::sort(small.begin(), small.end());
  return small;
}

}  // namespace csim
