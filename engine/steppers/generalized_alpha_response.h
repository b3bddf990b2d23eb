// The contact response of the nonsmooth generalized-α step (generalized_alpha.h) as its contact stage's
// iteration operator: for a row h of H, with S = M + hγc_w C + h²βc_w K the iteration matrix and
// c = h² c_w (β − γ/2) ≥ 0,
//   Z = M⁻¹ hᵀ,   G = S⁻¹ (hᵀ + c K Z),   W(a, b) = h_a · G_b,
// and an impulse R on the row moves v by R G, q by R [(hβ/γ) G + h(½ − β/γ) Z] and the smooth
// acceleration ẅ by R (G − Z)/(hγc_w). W is symmetric in exact arithmetic (M, C and K sharing their
// modes, which the stepper requires); its two triangles, which differ by the solves' round-off, are
// averaged. A row's columns are kept by its identity (contact key, row) while S and the row stay (a
// finite-element node resting or sliding on a plane).
//
// W stored by blocks (sparse_delassus): W(a, b) = h_a · G_b is zero unless G_b reaches an unknown of h_a,
// and G reaches only the unknowns that S, M and K couple to its row's: for bodies that no spring or
// elastic body joins (a pile of rigid points or discs), the rows of contacts that share a body. Each row
// keeps the unknowns its h and G reach; the blocks of rows reaching a common unknown are formed
// (block_pattern.h), each entry the same average of the two triangles as the dense W's.
#pragma once

#include "engine/contact_stage/iteration_operator.h"
#include "engine/linear_algebra/block_pattern.h"
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
  // By blocks, on the rule of iteration_operator.h (the stepper has no equality or tie row): unless
  // forced, at least kSparseRows rows and no unknown reached by more than kSparseDensity of the contacts.
  bool sparse_delassus(const ProblemRows& rows, SparseDelassus& W, bool forced) override;
  void add_response(const ProblemRows& rows, const Vector& r, Vector& v) override;
  // The jumps of impulses r on the rows of the last delassus(): v, q and ẅ as above.
  void add_jumps(const Vector& r, Vector& v, Vector& q, Vector& w) const;

 private:
  struct Columns {
    SparseRow row;
    Vector Z, G;
    std::vector<int> reach;  // the unknowns where h or G is nonzero (block_pattern.h)
    long factorization = -1;
    bool used = false;
  };
  using Key = std::pair<ContactKey, int>;
  const Columns& columns(const Key& key, const SparseRow& row);
  void take_columns(const ProblemRows& rows);  // row_columns_ for these rows, the others' dropped

  const StructuralOperators& operators_;
  const MassSolver& mass_;
  GeneralizedAlphaCoefficients coefficients_;
  double step_;
  std::map<Key, Columns> columns_;
  std::vector<const Columns*> row_columns_;  // the rows' of the last delassus() or sparse_delassus()
  std::vector<const std::vector<int>*> reach_;
  BlockPattern pattern_;
  Vector work_;
};

}  // namespace csim
