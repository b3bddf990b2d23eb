// SparseLdlt's solves (sparse_ldlt.h): a whole solve (CHOLMOD's), and the two halves of a solve around a
// contact solve, swept by supernodes over CHOLMOD's storage (supernodal_sweeps.h) or CHOLMOD's own
// where the layout is not ours: w = L⁻¹ P f, x = Pᵀ L⁻ᵀ D⁻¹ z, and solve_free, solve_with_reactions
// with the inverse block that delassus left.
#include "engine/linear_algebra/sparse_ldlt_storage.h"

#include <stdexcept>

namespace csim {

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

}  // namespace csim
