// The contact response of the nonsmooth generalized-α step (generalized_alpha.h) as its contact stage's
// iteration operator: for a row h of H, with S = M + hγc_w C + h²βc_w K the iteration matrix and
// c = h² c_w (β − γ/2) ≥ 0,
//   Z = M⁻¹ hᵀ,   G = S⁻¹ (hᵀ + c K Z),   W(a, b) = h_a · G_b,
// and an impulse R on the row moves v by R G, q by R [(hβ/γ) G + h(½ − β/γ) Z] and the smooth
// acceleration ẅ by R (G − Z)/(hγc_w). W is symmetric in exact arithmetic (M, C and K sharing their
// modes, which the stepper requires); its two triangles, which differ by the solves' round-off, are
// averaged. A row's columns are kept by its identity (contact key, row) while S and the row stay (a
// finite-element node resting or sliding on a plane).
#pragma once

#include "engine/contact_stage/iteration_operator.h"
#include "engine/mass_solver.h"
#include "engine/steppers/generalized_alpha_parameters.h"
#include "engine/structural_operators.h"

#include <map>
#include <utility>
#include <vector>

namespace csim {

class GeneralizedAlphaResponse final : public IterationOperator {
 public:
  GeneralizedAlphaResponse(const StructuralOperators& operators, const MassSolver& mass,
                           const GeneralizedAlphaCoefficients& coefficients, double step)
      : operators_(operators), mass_(mass), coefficients_(coefficients), step_(step) {}

  void delassus(const ProblemRows& rows, Matrix& W) override;
  void add_response(const ProblemRows& rows, const Vector& r, Vector& v) override;
  // The jumps of impulses r on the rows of the last delassus(): v, q and ẅ as above.
  void add_jumps(const Vector& r, Vector& v, Vector& q, Vector& w) const;

 private:
  struct Columns {
    SparseRow row;
    Vector Z, G;
    long factorization = -1;
    bool used = false;
  };
  using Key = std::pair<ContactKey, int>;
  const Columns& columns(const Key& key, const SparseRow& row);

  const StructuralOperators& operators_;
  const MassSolver& mass_;
  GeneralizedAlphaCoefficients coefficients_;
  double step_;
  std::map<Key, Columns> columns_;
  std::vector<const Columns*> row_columns_;  // the rows' of the last delassus()
  Vector work_;
};

}  // namespace csim
