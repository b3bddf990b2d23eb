// A⁻¹ of a sparse constant iteration matrix A = Pᵀ L D Lᵀ P (sparse_ldlt.h) through the forward columns
// y = L⁻¹ P hᵀ of the problem's rows, kept by the rows' identity while A stays (delassus_cache.h):
//   W(a, b) = y_aᵀ D⁻¹ y_b,   A⁻¹ Hᵀ r = Pᵀ L⁻ᵀ D⁻¹ (Σ_a r_a y_a)   (one backward substitution).
// A row entering costs one sparse forward substitution and its row of W; a node resting or sliding on a
// surface keeps its rows, and W is not copied again while its rows and entries hold.
//
// Two halves (Moreau–Jean's large linear World, moreau_jean.h): the free solve stops at its forward half,
// w = L⁻¹ P h f and z = D⁻¹ w; every candidate's rows (and the equalities') get their forward columns, and
// each row's h A⁻¹ f is y_cᵀ z (the dots of all of them in one pass over the columns stored by the factor's
// rows, forward_rows.h). The velocity after the contact solve is then v_k + Pᵀ L⁻ᵀ D⁻¹ (w + Y r): two
// passes over L a step instead of three (a large factor leaves the cache, and a pass is bound by memory).
#pragma once

#include "engine/contact_stage/delassus_cache.h"
#include "engine/contact_stage/two_halves_operator.h"
#include "engine/linear_algebra/block_gram.h"
#include "engine/linear_algebra/forward_rows.h"
#include "engine/state.h"

namespace csim {

class ForwardColumnsOperator final : public TwoHalvesOperator {
 public:
  explicit ForwardColumnsOperator(const StructuralOperators& operators) : operators_(operators) {}

  void delassus(const ProblemRows& rows, Matrix& W) override;
  // W = Yᵀ D⁻¹ Y by whole blocks (block_gram.h) from the rows' forward columns alone, the dense entries
  // never computed: for no equality or tie row (the contact solver condenses those on a dense W only)
  // and, unless forced, at least kSparseRows rows and no factor row reached by more than kSparseDensity
  // of the blocks.
  bool sparse_delassus(const ProblemRows& rows, SparseDelassus& W, bool forced) override;
  void add_response(const ProblemRows& rows, const Vector& r, Vector& v) override;

  // Two halves. The forward half of A⁻¹ f (f: N·s, the step's impulse of the smooth forces).
  void forward_half(const Vector& f) override;
  // The forward columns of every candidate's rows (rows: d a candidate), then of the equality rows;
  // their dots y_cᵀ z. Until the next call, delassus() takes its rows' columns from these
  // (ProblemRows::candidate_row).
  void gather_candidates(const std::vector<ActiveContact>& candidates, const std::vector<SparseRow>& rows,
                         int dimension, const Matrix* equalities) override;
  // Candidate row c's h A⁻¹ f as the row sees it: y_cᵀ z (for a normal row, u_n(v_free − v_k)).
  double free_dot(int c) const override { return candidate_dots_[c]; }
  const std::vector<double>& free_dots() const { return candidate_dots_; }
  // v ← v_k + A⁻¹ f (the whole free velocity, one backward pass: a step taken again).
  void free_velocity(const Vector& v_k, Vector& v) const override;
  // v ← v_k + A⁻¹ (f + Hᵀ r) = v_k + Pᵀ L⁻ᵀ D⁻¹ (w + Y r), H the rows of the last delassus().
  void velocity(const ProblemRows& rows, const Vector& r, const Vector& v_k, Vector& v) override;

 private:
  int equality_slot(const Matrix& equalities, int e);
  void take_slots(const ProblemRows& rows);  // slots_ of these rows (their forward columns up to date)

  const StructuralOperators& operators_;
  DelassusCache cache_;
  std::vector<int> slots_;              // each problem row's slot in the cache
  bool slots_taken_ = false;            // sparse_delassus took slots_ and declined: delassus() uses them
  std::vector<const SparseLdlt::ForwardColumn*> columns_;  // sparse_delassus' forward columns, by row
  BlockGram block_gram_;                // sparse_delassus' assembly, with its work space
  DelassusCache::Taken copied_;         // the slots W was last copied from
  DelassusCache::Taken sparse_taken_;   // the slots the sparse W was last formed from
  std::vector<int> equality_index_;     // an equality row's nonzeros (work space)
  std::vector<double> equality_value_;
  Vector sum_, work_;                   // Y r (the factor's order), and the backward pass's result
  bool halves_ = false;                 // gather_candidates was called for this step
  Vector free_forward_, free_scaled_;   // w = L⁻¹ P f and z = D⁻¹ w
  std::vector<int> candidate_slots_;
  ForwardRows forward_rows_;
  std::vector<double> candidate_dots_, candidate_impulses_;
  std::vector<char> candidate_in_problem_;
};

}  // namespace csim
