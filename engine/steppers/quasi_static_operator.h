// The quasi-static stepper's iteration matrix as its contact stage sees it (iteration_operator.h). A is the
// factored stiffness over the unknowns z (K_z, held positive definite by held rows or proximal terms, or
// an earlier iterate's kept factor: quasi_static.h), so the problem's rows are the contact rows mapped to
// z by the reduced coordinates' tangent T = ∂q/∂z (reduced_coordinates.h), H_z = H T, and
//   W = H_z A⁻¹ H_zᵀ,   b = H_z A⁻¹ f + c,   Δz = A⁻¹ (f + H_zᵀ r),
// f (N, N·m) the load that goes with A, c the gaps and slips (m, the stepper's), r the contact forces (N).
// The problem has Moreau–Jean's form with a position increment (m, rad) where Moreau–Jean has a velocity
// and a force where it has an impulse. The free term and the increment are the two halves of one solve
// (SparseLdlt::solve_free, solve_with_reactions): one forward and one backward substitution for the pair,
// where A⁻¹ f and A⁻¹ H_zᵀ r would take two of each. The factor and T are the stepper's, refactored and
// updated between calls; W takes the factor as it is when the stage forms it.
#pragma once

#include "engine/contact_stage/iteration_operator.h"
#include "engine/linear_algebra/sparse_ldlt.h"
#include "engine/reduced_coordinates.h"

#include <vector>

namespace csim {

class QuasiStaticOperator final : public IterationOperator {
 public:
  QuasiStaticOperator(SparseLdlt& factor, const SparseRowMatrix& T) : factor_(factor), T_(T) {}

  // H_z ← H T for the rows the stage just gathered (contact rows only: the stepper has no equality rows).
  void gather(const ProblemRows& rows) override;
  const Matrix& reduced_rows() const { return H_; }  // H_z, m × |z|, dense

  void delassus(const ProblemRows& rows, Matrix& W) override;
  // v += A⁻¹ H_zᵀ r (v over z).
  void add_response(const ProblemRows& rows, const Vector& r, Vector& v) override;
  // u = H_z v (v over z).
  void apply_rows(const ProblemRows&, const Vector& v, Vector& u) const override { u.noalias() = H_ * v; }

  // b ← H_z A⁻¹ f, after delassus with the same factor (the first half of the solve; m > 0).
  void load_term(const Vector& f, Vector& b) { factor_.solve_free(f, b); }
  // Δz ← A⁻¹ (f + H_zᵀ r), f the last load_term's (the second half).
  void increment(const Vector& r, Vector& dz) { factor_.solve_with_reactions(r, dz); }

 private:
  SparseLdlt& factor_;
  const SparseRowMatrix& T_;
  Matrix H_;                             // H_z
  std::vector<Eigen::Index> H_written_;  // the entries of H_ the last gather wrote (the others are zero)
  Vector work_;
};

}  // namespace csim
