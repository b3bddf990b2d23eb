// M⁻¹ of a World's mass matrix (kg, kg·m²; constant): for the schemes that split a velocity jump
// M⁻¹ Hᵀ P off the smooth motion (the nonsmooth generalized-α scheme, generalized_alpha.h) and take
// the initial acceleration M⁻¹ f(0). Factored once: a dense LDLᵀ for small Worlds, CHOLMOD's
// simplicial LDLᵀ (sparse_ldlt.h) for finite-element ones. A zero or negative mass pivot (a body
// without mass on some coordinate) is refused when the solver is made.
#pragma once

#include "engine/dynamics.h"
#include "engine/linear_algebra/sparse_ldlt.h"

#include <Eigen/Dense>

namespace csim {

class MassSolver {
 public:
  static constexpr int kDenseLimit = 64;  // as StructuralOperators'

  // Throws std::invalid_argument when M is not positive definite.
  explicit MassSolver(const Dynamics& dynamics);
  void solve_in_place(Vector& x) const;  // x ← M⁻¹ x

 private:
  bool sparse_;
  Eigen::LDLT<Matrix> dense_;
  SparseLdlt sparse_factor_;
};

}  // namespace csim
