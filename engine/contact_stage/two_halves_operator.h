// An operator of A that a stepper may also take in two halves (Moreau–Jean's linear World, moreau_jean.h):
// the free solve stopped before the detection, each candidate row's part h A⁻¹ f of it given as a dot, and
// the velocity after the contact solve formed at once, v_k + A⁻¹ (f + Hᵀ r). A sparse constant A keeps its
// forward columns for it (forward_columns.h); an A block diagonal by body applies A⁻¹ body by body
// (body_block_operator.h). f: N·s, velocities m/s.
#pragma once

#include "engine/contact_stage/iteration_operator.h"
#include "engine/state.h"

#include <vector>

namespace csim {

class TwoHalvesOperator : public IterationOperator {
 public:
  // The first half of A⁻¹ f (f: the step's impulse of the smooth forces).
  virtual void forward_half(const Vector& f) = 0;
  // Every candidate's rows (d a candidate), then the equality rows: their free dots h A⁻¹ f.
  virtual void gather_candidates(const std::vector<ActiveContact>& candidates, const std::vector<SparseRow>& rows,
                                 int dimension, const Matrix* equalities) = 0;
  // Candidate row c's h A⁻¹ f (for a normal row, u_n(v_free − v_k)).
  virtual double free_dot(int c) const = 0;
  // v ← v_k + A⁻¹ f (the whole free velocity: a step taken again).
  virtual void free_velocity(const Vector& v_k, Vector& v) const = 0;
  // v ← v_k + A⁻¹ (f + Hᵀ r), H the rows of the last delassus().
  virtual void velocity(const ProblemRows& rows, const Vector& r, const Vector& v_k, Vector& v) = 0;
};

}  // namespace csim
