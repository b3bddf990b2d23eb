// The check that our kernels may read a CHOLMOD factor's arrays (cholmod_layout_supported, sparse_ldlt.h),
// and CHOLMOD's own routines where they may not (or where Kernels::cholmod, cholmod_ll ask for them):
// the sparse forward solve with Bset and Xset, the halves of a solve, the pivots D.
#include "engine/linear_algebra/sparse_ldlt_storage.h"

#include <algorithm>
#include <stdexcept>

namespace csim {

namespace {

// The CHOLMOD versions whose simplicial factor our kernels read: 3.x (cholmod_core.h) to 5.x (cholmod.h)
// document the same layout of it. Another version builds, and its factors are read by CHOLMOD alone.
#if CHOLMOD_MAIN_VERSION < 3 || CHOLMOD_MAIN_VERSION > 5
#pragma message("sparse_ldlt_cholmod.cpp: a CHOLMOD version whose factor layout is not known here; CHOLMOD's routines read it")
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

}  // namespace csim
