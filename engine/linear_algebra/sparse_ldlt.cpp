#include "engine/linear_algebra/sparse_ldlt.h"

#include <cholmod.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace csim {

struct SparseLdlt::Cholmod {
  cholmod_common common;
  cholmod_factor* factor = nullptr;
  // cholmod_solve2's result and work space, reused from solve to solve.
  cholmod_dense* x = nullptr;
  cholmod_dense* y = nullptr;
  cholmod_dense* e = nullptr;
  // forward_by_cholmod's: the sparse solve's result, work space, right-hand side's pattern (Bset) and
  // the solution's (Xset), and its dense right-hand side (zero between calls).
  cholmod_dense* sparse_x = nullptr;
  cholmod_dense* sparse_y = nullptr;
  cholmod_dense* sparse_e = nullptr;
  cholmod_sparse* bset = nullptr;
  cholmod_sparse* xset = nullptr;
  Vector sparse_b;
  double analysed_nonzeros = 0.0;  // entries of L by the last analysis (CHOLMOD's count)
  std::vector<int> permutation;  // the unknown at each position of the factor's order (P)
  std::vector<int> inverse;      // position in the factor's order of each unknown
  // triu(P A Pᵀ), compressed by columns, rows sorted: what the factorization reads as it is. slot[p] is
  // the place in upper_value of A's p-th stored entry, −1 for an entry above A's diagonal (not read).
  std::vector<int> upper_start, upper_row, slot;
  std::vector<double> upper_value;
  Vector permuted;  // a right-hand side in the factor's order, for solves

  Cholmod() {
    cholmod_start(&common);
    common.supernodal = CHOLMOD_SIMPLICIAL;
    common.final_asis = 1;  // keep LDLᵀ: D's pivots say whether A > 0
    common.nmethods = 1;
    common.print = 1;  // errors only: a non-positive pivot is an answer here, not a warning
  }
  ~Cholmod() {
    if (factor) cholmod_free_factor(&factor, &common);
    cholmod_free_dense(&x, &common);
    cholmod_free_dense(&y, &common);
    cholmod_free_dense(&e, &common);
    cholmod_free_dense(&sparse_x, &common);
    cholmod_free_dense(&sparse_y, &common);
    cholmod_free_dense(&sparse_e, &common);
    cholmod_free_sparse(&bset, &common);
    cholmod_free_sparse(&xset, &common);
    cholmod_finish(&common);
  }
  int* column_start() const { return static_cast<int*>(factor->p); }
  int* column_count() const { return static_cast<int*>(factor->nz); }
  int* row_index() const { return static_cast<int*>(factor->i); }
  double* values() const { return static_cast<double*>(factor->x); }
};

namespace {

// A compressed symmetric matrix as CHOLMOD reads it, without a copy: its lower triangle (stype −1) or
// its upper one (stype +1).
cholmod_sparse view_triangle(int n, const int* start, const int* row, const double* value, int stype) {
  cholmod_sparse view{};
  view.nrow = static_cast<std::size_t>(n);
  view.ncol = static_cast<std::size_t>(n);
  view.nzmax = static_cast<std::size_t>(start[n]);
  view.p = const_cast<int*>(start);
  view.i = const_cast<int*>(row);
  view.x = const_cast<double*>(value);
  view.stype = stype;
  view.itype = CHOLMOD_INT;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = 1;
  view.packed = 1;
  return view;
}

// A column of n numbers as CHOLMOD reads a right-hand side, without a copy.
cholmod_dense dense_view(double* value, int n) {
  cholmod_dense view{};
  view.nrow = static_cast<std::size_t>(n);
  view.ncol = 1;
  view.nzmax = view.nrow;
  view.d = view.nrow;
  view.x = value;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  return view;
}

// The CHOLMOD versions whose simplicial factor our kernels read: 3.x (cholmod_core.h) to 5.x (cholmod.h)
// document the same layout of it. Another version builds, and its factors are read by CHOLMOD alone.
#if CHOLMOD_MAIN_VERSION < 3 || CHOLMOD_MAIN_VERSION > 5
#pragma message("sparse_ldlt.cpp: a CHOLMOD version whose factor layout is not known here; CHOLMOD's routines read it")
#endif
constexpr bool kKnownCholmod = CHOLMOD_MAIN_VERSION >= 3 && CHOLMOD_MAIN_VERSION <= 5;

// The library's main version that of the header (a library swapped under the binary), asked once.
bool library_is_the_header_version() {
  static const bool same = cholmod_version(nullptr) / 1000 == CHOLMOD_MAIN_VERSION;
  return same;
}

}  // namespace

bool cholmod_layout_supported(const cholmod_factor& factor) {
  if (!kKnownCholmod || !library_is_the_header_version()) return false;
  if (factor.xtype != CHOLMOD_REAL || factor.dtype != CHOLMOD_DOUBLE || factor.itype != CHOLMOD_INT) return false;
  if (factor.is_super || factor.is_ll || factor.ordering != CHOLMOD_NATURAL) return false;
  if (!factor.p || !factor.i || !factor.nz || !factor.x) return false;
  const int* start = static_cast<const int*>(factor.p);
  const int* row = static_cast<const int*>(factor.i);
  const int n = static_cast<int>(factor.n);
  for (int j = 0; j < n; ++j)
    if (row[start[j]] != j) return false;
  return true;
}

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
  c.common.postorder = 1;
  cholmod_sparse lower = view_triangle(n, outer, inner, A.valuePtr(), -1);
  double fewest = std::numeric_limits<double>::infinity();
  for (const int method : {CHOLMOD_AMD, CHOLMOD_METIS}) {
    c.common.method[0].ordering = method;
    cholmod_factor* ordering = cholmod_analyze(&lower, &c.common);
    if (!ordering) {
      if (method == CHOLMOD_AMD) throw std::runtime_error("CHOLMOD could not analyse the matrix (out of memory?)");
      continue;  // METIS is optional
    }
    if (c.common.fl < fewest) {
      fewest = c.common.fl;
      const int* permutation = static_cast<const int*>(ordering->Perm);
      c.permutation.assign(permutation, permutation + n);
    }
    cholmod_free_factor(&ordering, &c.common);
  }
  c.inverse.resize(n);
  for (int k = 0; k < n; ++k) c.inverse[c.permutation[k]] = k;
  // A's entry (i, j), i ≥ j, goes to (min, max) of (P i, P j), in the order CHOLMOD's permuted transpose
  // (cholmod_transpose_sym) lays them: the columns of P A Pᵀ in turn, each entry appended to its column
  // of the upper triangle. The simplicial factorization's sums follow the order of a column's entries,
  // so that this order, not only the values, gives CHOLMOD's factor bit for bit.
  c.upper_start.assign(n + 1, 0);
  for (int j = 0; j < n; ++j) {
    const int old = c.permutation[j];
    for (int p = outer[old]; p < outer[old + 1]; ++p)
      if (inner[p] >= old) ++c.upper_start[std::max(c.inverse[inner[p]], j) + 1];
  }
  for (int j = 0; j < n; ++j) c.upper_start[j + 1] += c.upper_start[j];
  std::vector<int> fill(c.upper_start.begin(), c.upper_start.end() - 1);
  c.upper_row.resize(c.upper_start[n]);
  c.upper_value.assign(c.upper_start[n], 0.0);
  c.slot.assign(nnz, -1);  // above the diagonal: CHOLMOD reads the lower triangle only
  for (int j = 0; j < n; ++j) {
    const int old = c.permutation[j];
    for (int p = outer[old]; p < outer[old + 1]; ++p) {
      if (inner[p] < old) continue;
      const int i = c.inverse[inner[p]];
      const int position = fill[std::max(i, j)]++;
      c.upper_row[position] = std::min(i, j);
      c.slot[p] = position;
    }
  }
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

// x ← Pᵀ (L D Lᵀ)⁻¹ P x: the factor is of P A Pᵀ.
void SparseLdlt::solve_in_place(Vector& b) const {
  Cholmod& c = *cholmod_;
  const int n = static_cast<int>(b.size());
  c.permuted.resize(n);
  for (int k = 0; k < n; ++k) c.permuted(k) = b(c.permutation[k]);
  cholmod_dense rhs = dense_view(c.permuted.data(), n);
  if (!cholmod_solve2(CHOLMOD_A, c.factor, &rhs, nullptr, &c.x, nullptr, &c.y, &c.e, &c.common))
    throw std::runtime_error("CHOLMOD could not solve (out of memory?)");
  const double* x = static_cast<const double*>(c.x->x);
  for (int k = 0; k < n; ++k) b(c.permutation[k]) = x[k];
}

Vector SparseLdlt::solve(const Vector& b) const {
  Vector x = b;
  solve_in_place(x);
  return x;
}

// The parent of each column of L in the elimination tree (its first subdiagonal row: L's columns are
// sorted, and the smallest row is taken whatever the order) and the pivots D.
void SparseLdlt::prepare_tree() const {
  if (tree_ready_) return;
  const Cholmod& c = *cholmod_;
  const int n = size();
  if (!ours_) {  // CHOLMOD's forward columns need no tree
    cholmod_pivots(pivots_, false);
    tree_ready_ = true;
    return;
  }
  const int* start = c.column_start();
  const int* count = c.column_count();
  const int* row = c.row_index();
  const double* x = c.values();
  parent_.assign(n, -1);
  pivots_.resize(n);
  for (int j = 0; j < n; ++j) {
    pivots_(j) = x[start[j]];
    int first = n;
    for (int q = start[j] + 1; q < start[j] + count[j]; ++q) first = std::min(first, row[q]);
    if (first < n) parent_[j] = first;
  }
  if (static_cast<int>(mark_.size()) != n) mark_.assign(n, 0);
  work_.setZero(n);
  tree_ready_ = true;
}

void SparseLdlt::forward(const int* index, const double* value, int count, ForwardColumn& y) const {
  prepare_tree();
  if (!ours_) return forward_by_cholmod(index, value, count, y);
  const Cholmod& c = *cholmod_;
  // The reach: every column on the paths from the right-hand side's nonzeros to the root (marks are
  // cleared on the way out, so that the next call starts from zero), in ascending order, so that a
  // column's ancestors come after it. Each path ascends (a parent comes after its child), so that the
  // reach is the merge of the new part of each path into the reach so far, where a sort of the whole
  // took a ninth of the time of a column at 13k unknowns (bench_factor's forward table).
  reach_.clear();
  for (int k = 0; k < count; ++k) {
    int j = c.inverse[index[k]];
    work_(j) += value[k];
    const std::size_t before = reach_.size();
    for (; j >= 0 && !mark_[j]; j = parent_[j]) {
      mark_[j] = 1;
      reach_.push_back(j);
    }
    if (before > 0 && reach_.size() > before) {
      merged_.resize(reach_.size());
      std::merge(reach_.begin(), reach_.begin() + static_cast<std::ptrdiff_t>(before), reach_.begin() + static_cast<std::ptrdiff_t>(before),
                 reach_.end(), merged_.begin());
      reach_.swap(merged_);
    }
  }
  const int* start = c.column_start();
  const int* column_count = c.column_count();
  const int* row = c.row_index();
  const double* x = c.values();
  y.index.resize(reach_.size());
  y.value.resize(reach_.size());
  for (std::size_t k = 0; k < reach_.size(); ++k) {
    const int j = reach_[k];
    const double yj = work_(j);
    for (int q = start[j] + 1; q < start[j] + column_count[j]; ++q) work_(row[q]) -= x[q] * yj;
    y.index[k] = j;
    y.value[k] = yj;
    work_(j) = 0.0;
    mark_[j] = 0;
  }
}

// CHOLMOD's sparse forward solve, L y = P hᵀ for the pattern of P hᵀ (Bset): it finds y's pattern
// (Xset, unsorted: the reach), which is sorted here as a ForwardColumn's rows are.
void SparseLdlt::forward_by_cholmod(const int* index, const double* value, int count, ForwardColumn& y) const {
  Cholmod& c = *cholmod_;
  const int n = size();
  if (!c.bset || static_cast<int>(c.bset->nrow) != n) {
    cholmod_free_sparse(&c.bset, &c.common);
    c.bset = cholmod_allocate_sparse(n, 1, n, 0, 1, 0, CHOLMOD_PATTERN, &c.common);
    if (!c.bset) throw std::runtime_error("CHOLMOD could not allocate (out of memory?)");
    c.sparse_b.setZero(n);
  }
  int* set = static_cast<int*>(c.bset->i);
  static_cast<int*>(c.bset->p)[0] = 0;
  static_cast<int*>(c.bset->p)[1] = count;
  for (int k = 0; k < count; ++k) {
    set[k] = c.inverse[index[k]];
    c.sparse_b(set[k]) += value[k];
  }
  cholmod_dense rhs = dense_view(c.sparse_b.data(), n);
  const int solved = cholmod_solve2(CHOLMOD_L, c.factor, &rhs, c.bset, &c.sparse_x, &c.xset, &c.sparse_y, &c.sparse_e, &c.common);
  for (int k = 0; k < count; ++k) c.sparse_b(set[k]) = 0.0;
  if (!solved) throw std::runtime_error("CHOLMOD could not solve (out of memory?)");
  const int* rows = static_cast<const int*>(c.xset->i);
  const int length = static_cast<const int*>(c.xset->p)[1];
  y.index.assign(rows, rows + length);
  std::sort(y.index.begin(), y.index.end());
  const double* x = static_cast<const double*>(c.sparse_x->x);
  y.value.resize(length);
  for (int k = 0; k < length; ++k) y.value[k] = x[y.index[k]];
}

void SparseLdlt::solve_by_cholmod(int system, double* x) const {
  Cholmod& c = *cholmod_;
  const int n = size();
  cholmod_dense rhs = dense_view(x, n);
  if (!cholmod_solve2(system, c.factor, &rhs, nullptr, &c.x, nullptr, &c.y, &c.e, &c.common))
    throw std::runtime_error("CHOLMOD could not solve (out of memory?)");
  std::copy_n(static_cast<const double*>(c.x->x), n, x);
}

// D from D⁻¹ 1 (CHOLMOD_D): D of an LDLᵀ factor, 1 for an LLᵀ one, whose columns hold D^½ (the pivots
// that its forward columns go with). With of_ldlt, D of the LDLᵀ factorization whatever the factor (an
// LLᵀ one converted on a copy by CHOLMOD: L_jj²).
void SparseLdlt::cholmod_pivots(Vector& D, bool of_ldlt) const {
  Cholmod& c = *cholmod_;
  const int n = size();
  cholmod_factor* factor = c.factor;
  if (of_ldlt && factor->is_ll) {
    factor = cholmod_copy_factor(c.factor, &c.common);
    if (!factor || !cholmod_change_factor(CHOLMOD_REAL, 0, 0, 1, 1, factor, &c.common)) {
      cholmod_free_factor(&factor, &c.common);
      throw std::runtime_error("CHOLMOD could not convert the factor (out of memory?)");
    }
  }
  D.setOnes(n);
  cholmod_dense ones = dense_view(D.data(), n);
  const int solved = cholmod_solve2(CHOLMOD_D, factor, &ones, nullptr, &c.x, nullptr, &c.y, &c.e, &c.common);
  if (factor != c.factor) cholmod_free_factor(&factor, &c.common);
  if (!solved) throw std::runtime_error("CHOLMOD could not solve (out of memory?)");
  const double* x = static_cast<const double*>(c.x->x);
  for (int j = 0; j < n; ++j) D(j) = 1.0 / x[j];
}

double SparseLdlt::delassus_entry(const ForwardColumn& a, const ForwardColumn& b) const {
  double sum = 0.0;
  std::size_t p = 0, q = 0;
  while (p < a.index.size() && q < b.index.size()) {
    if (a.index[p] < b.index[q]) {
      ++p;
    } else if (b.index[q] < a.index[p]) {
      ++q;
    } else {
      sum += a.value[p] * b.value[q] / pivots_(a.index[p]);
      ++p;
      ++q;
    }
  }
  return sum;
}

const SupernodalSweeps& SparseLdlt::sweeps() const {
  if (!sweeps_ready_) {
    const Cholmod& c = *cholmod_;
    sweeps_.analyse(size(), c.column_start(), c.column_count(), c.row_index());
    sweeps_ready_ = true;
  }
  return sweeps_;
}

void SparseLdlt::back_substitute(const Vector& z, Vector& x) const {
  Cholmod& c = *cholmod_;
  const int n = size();
  c.permuted = z;
  if (ours_)
    sweeps().backward(c.column_start(), c.values(), c.permuted.data());
  else
    solve_by_cholmod(CHOLMOD_DLt, c.permuted.data());
  x.resize(n);
  for (int k = 0; k < n; ++k) x(c.permutation[k]) = c.permuted(k);
}

void SparseLdlt::scatter_scaled(const ForwardColumn& y, Vector& x) const {
  for (std::size_t k = 0; k < y.index.size(); ++k) x(y.index[k]) = y.value[k] / pivots_(y.index[k]);
}

double SparseLdlt::dot(const ForwardColumn& y, const Vector& x) {
  double sum = 0.0;
  for (std::size_t k = 0; k < y.index.size(); ++k) sum += y.value[k] * x(y.index[k]);
  return sum;
}

void SparseLdlt::add_scaled(double a, const ForwardColumn& y, Vector& x) {
  for (std::size_t k = 0; k < y.index.size(); ++k) x(y.index[k]) += a * y.value[k];
}

// L⁻¹ P f into w.
void SparseLdlt::forward_sweep(const Vector& f, Vector& w) const {
  const Cholmod& c = *cholmod_;
  const int n = size();
  w.resize(n);
  for (int k = 0; k < n; ++k) w(k) = f(c.permutation[k]);
  if (ours_)
    sweeps().forward(c.column_start(), c.values(), w.data());
  else
    solve_by_cholmod(CHOLMOD_L, w.data());
}

void SparseLdlt::forward_substitute(const Vector& f, Vector& w, Vector& z) const {
  if (&f == &w) throw std::logic_error("SparseLdlt::forward_substitute: w must not be f");
  prepare_tree();
  forward_sweep(f, w);
  z = w.cwiseQuotient(pivots_);
}

void SparseLdlt::solve_free(const Vector& f, Vector& Hx) {
  const int s = static_cast<int>(unknowns_.size());
  if (gram_factorization_ != factorizations_) throw std::logic_error("SparseLdlt::solve_free before delassus");
  forward_sweep(f, free_forward_);
  // E_Sᵀ A⁻¹ f = Y_Sᵀ D⁻¹ w.
  block_values_.resize(s);
  for (int j = 0; j < s; ++j) {
    double sum = 0.0;
    const ForwardColumn& y = columns_[j];
    for (std::size_t k = 0; k < y.index.size(); ++k) sum += y.value[k] * free_forward_(y.index[k]) / pivots_(y.index[k]);
    block_values_(j) = sum;
  }
  Hx.noalias() = rows_on_unknowns_ * block_values_;
}

void SparseLdlt::solve_with_reactions(const Vector& r, Vector& x) {
  const int s = static_cast<int>(unknowns_.size());
  block_values_.noalias() = rows_on_unknowns_.transpose() * r;
  for (int j = 0; j < s; ++j) add_scaled(block_values_(j), columns_[j], free_forward_);
  back_substitute(free_forward_, x);
}

// G = E_Sᵀ A⁻¹ E_S for the unknowns S that H's rows touch, from their unit forward columns, and then
// W = H_S G H_Sᵀ (see the header).
void SparseLdlt::delassus(const Matrix& H, Matrix& W) {
  const int m = static_cast<int>(H.rows()), n = static_cast<int>(H.cols());
  W.resize(m, m);
  if (m == 0) return;
  touched_.clear();
  for (int k = 0; k < n; ++k)
    for (int a = 0; a < m; ++a)
      if (H(a, k) != 0.0) {
        touched_.push_back(k);
        break;
      }
  const int s = static_cast<int>(touched_.size());
  if (gram_factorization_ == factorizations_ && touched_ == unknowns_) {
    ++kept_delassus_;
  } else {
    std::swap(unknowns_, touched_);
    inverse_block();
    gram_factorization_ = factorizations_;
  }
  rows_on_unknowns_.resize(m, s);
  for (int j = 0; j < s; ++j) rows_on_unknowns_.col(j) = H.col(unknowns_[j]);
  rows_times_block_.noalias() = rows_on_unknowns_ * gram_;
  // The lower triangle, mirrored: W symmetric to the bit, as the contact solvers read it.
  for (int b = 0; b < m; ++b)
    for (int a = b; a < m; ++a) W(a, b) = W(b, a) = rows_times_block_.row(a).dot(rows_on_unknowns_.row(b));
}

// gram_ ← E_Sᵀ A⁻¹ E_S = Yᵀ D⁻¹ Y, Y = L⁻¹ P E_S, S = unknowns_: each column of Y is the forward
// substitution of one unknown, which fills only that unknown's path to the root of the elimination tree.
void SparseLdlt::inverse_block() {
  const int n = size(), s = static_cast<int>(unknowns_.size());
  gram_.resize(s, s);
  // Y's sparse columns, and Y_ dense, which is zero between calls (the entries written are cleared at the
  // end, not all n × s).
  if (Y_.rows() != n || Y_.cols() < s) Y_.setZero(n, std::max<Eigen::Index>(s, Y_.cols()));
  columns_.resize(s);
  const double one = 1.0;
  for (int c = 0; c < s; ++c) {
    forward(&unknowns_[c], &one, 1, columns_[c]);
    for (std::size_t k = 0; k < columns_[c].index.size(); ++k) Y_(columns_[c].index[k], c) = columns_[c].value[k];
  }
  // The columns that reach each row of Y with a nonzero, in column order, from the sparse columns.
  row_start_.assign(n + 1, 0);
  for (int c = 0; c < s; ++c)
    for (std::size_t k = 0; k < columns_[c].index.size(); ++k)
      if (columns_[c].value[k] != 0.0) ++row_start_[columns_[c].index[k] + 1];
  for (int i = 0; i < n; ++i) row_start_[i + 1] += row_start_[i];
  row_columns_.resize(row_start_[n]);
  fill_.assign(row_start_.begin(), row_start_.end() - 1);
  for (int c = 0; c < s; ++c)
    for (std::size_t k = 0; k < columns_[c].index.size(); ++k)
      if (columns_[c].value[k] != 0.0) row_columns_[fill_[columns_[c].index[k]]++] = c;
  // G = Σ_i y_i y_iᵀ / D_i over the rows y_i of Y (D > 0: a positive definite factor). A row that few
  // columns reach (below the top separators of the elimination tree) adds its few products directly; the
  // denser rows, scaled by D^-1/2, go to one matrix product.
  const Vector& D = pivots_;
  gram_.setZero();
  rows_.clear();
  for (int i = 0; i < n; ++i) {
    const int* columns = row_columns_.data() + row_start_[i];
    const int k = row_start_[i + 1] - row_start_[i];
    if (k == 0) continue;
    if (3 * k > s) {
      rows_.push_back(i);
      continue;
    }
    for (int p = 0; p < k; ++p) {
      const double scaled = Y_(i, columns[p]) / D(i);
      for (int q = 0; q <= p; ++q) gram_(columns[q], columns[p]) += scaled * Y_(i, columns[q]);
    }
  }
  compact_.resize(static_cast<Eigen::Index>(rows_.size()), s);
  for (int k = 0; k < static_cast<int>(rows_.size()); ++k)
    compact_.row(k) = Y_.row(rows_[k]).head(s) / std::sqrt(D(rows_[k]));
  gram_.triangularView<Eigen::StrictlyLower>() = gram_.transpose().triangularView<Eigen::StrictlyLower>();
  gram_.noalias() += compact_.transpose() * compact_;
  for (int c = 0; c < s; ++c)
    for (int i : columns_[c].index) Y_(i, c) = 0.0;
}

}  // namespace csim
