// SparseLdlt's CHOLMOD state: the factor, the work spaces of CHOLMOD's solves, the ordering P and the
// map of A's lower triangle into triu(P A Pᵀ) (sparse_ldlt.h), and views of our arrays as CHOLMOD's
// structs (no copies). For the files that implement SparseLdlt only: sparse_ldlt.cpp (analysis and
// factorization), sparse_ldlt_cholmod.cpp (the layout check and CHOLMOD's own routines),
// sparse_ldlt_solves.cpp (solves and their halves), sparse_ldlt_delassus.cpp (forward columns and W).
// CHOLMOD's header stays out of sparse_ldlt.h, which its users include.
#pragma once

#include "engine/linear_algebra/sparse_ldlt.h"

#include <cholmod.h>

#include <vector>

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
  // The ordering P of A's pattern (permutation and inverse), from A's lower triangle.
  void choose_ordering(int n, const int* outer, const int* inner, const double* value);
  // upper_start, upper_row and slot: where each entry of A's lower triangle goes in triu(P A Pᵀ).
  void map_to_permuted_upper(int n, int nnz, const int* outer, const int* inner);
  int* column_start() const { return static_cast<int*>(factor->p); }
  int* column_count() const { return static_cast<int*>(factor->nz); }
  int* row_index() const { return static_cast<int*>(factor->i); }
  double* values() const { return static_cast<double*>(factor->x); }
};

// A compressed symmetric matrix as CHOLMOD reads it, without a copy: its lower triangle (stype −1) or
// its upper one (stype +1).
inline cholmod_sparse view_triangle(int n, const int* start, const int* row, const double* value, int stype) {
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
inline cholmod_dense dense_view(double* value, int n) {
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

}  // namespace csim
