// The length of a Newton step from the secant model of the last two (Aitken's Δ² along one slow mode).
// Used by the quasi-static and Moreau–Jean steppers, whose Newton iterations hold an indefinite or
// nearly singular matrix with a proximal term, or leave the contact's own geometric stiffness out of
// their model: the iteration then converges linearly, or oscillates, along the mode the model gets wrong.
//
// Along one slow mode, Newton meets Δx_j ≈ ρ Δx_{j−1} (ρ = Δx_j·Δx_{j−1}/|Δx_{j−1}|²), and if its
// model's stiffness there is the true one over c, ρ = 1 − ω_{j−1} c, so that the step that reaches the
// fixed point of the scalar model is ω_j = ω_{j−1}/(1 − ρ). Two cases use it:
//   oscillation, ρ < −½ (each step reversing most of the last): the model is too soft along the mode.
//     (the contact's geometric stiffness, on the proximal path, is not in K_z);
//   slow monotone convergence, ½ < ρ < 1 with aligned steps and ρ steady over two iterations (Aitken's
//     extrapolation of a linear rate): the model is too stiff along a mode that the contacts barely
//     hold (a proximal term on a spin that a slipping patch leaves free). The cases that showed both
//     behaviours are in docs/solver-measurements.md.
// Capped at kMostExtrapolation; not taken again right after a relaxed step, whose ρ measures the
// relaxation as much as the model. The relaxed iterate is only a starting point: the next iteration's
// residual and contact solve are exact, so the converged state is Newton's.
#pragma once

#include "engine/bodies/body.h"  // Vector

namespace csim {

class SecantRelaxation {
 public:
  // At a step's first iteration: no rate to measure yet.
  void reset() { previous_step_.resize(0); }
  // ω_j for x_{j+1} = x_j + ω_j Δx_j, from Δx_j and the steps seen since reset().
  double next(const Vector& step);

 private:
  Vector previous_step_;
  double previous_relaxation_ = 1.0, previous_ratio_ = 0.0;
};

}  // namespace csim
