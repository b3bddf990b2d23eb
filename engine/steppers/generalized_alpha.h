// The nonsmooth generalized-α scheme (Q.Z. Chen, V. Acary, G. Virlez, O. Brüls, IJNME 96, 2013;
// energy properties: V. Acary, ZAMM 96, 2016): the smooth motion by the generalized-α method of
// Chung & Hulbert (second order, the high frequencies damped to ρ∞), the contacts by impulses at the
// velocity level, solved as the same {W, b, μ} problem as Moreau–Jean's (PGS, local Coulomb solves).
// The contact forces stay out of the generalized-α recursion, so that an impact does not ring through
// its acceleration memory; what the step does not resolve (an FE shoe's stiff modes excited by the
// contact switches) is damped to ρ∞, and what it resolves keeps second order (Moreau–Jean with θ > ½
// damps everything at first order).
//
// Unknowns of a step from t_n to t_{n+1} = t_n + h: q, v, the smooth acceleration ẅ (contacts left
// out: M ẅ = f(t, q, v) of dynamics.h), the recursion's acceleration a, and the impulse P on the
// contact rows H (its velocity jump u = M⁻¹ Hᵀ P):
//   (1 − α_m) a_{n+1} + α_m a_n = (1 − α_f) ẅ_{n+1} + α_f ẅ_n,
//   v_{n+1} = v_n + h(1 − γ) a_n + hγ a_{n+1} + u,
//   q_{n+1} = q_n + h v_n + h²(½ − β) a_n + h²β a_{n+1} + ½ h u,
//   M ẅ_{n+1} = f_loads(t_{n+1}) + f_int(q_n) − K(q_n)(q_{n+1} − q_n) − C v_{n+1}
// (the internal force linearized at q_n: exact for linear bodies, O(|Δq|²) for springs on turning
// points). The jump enters q with weight ½ h, the trapezoid of the velocities: a sticking or resting
// contact then stays where it is to O(h³) a step, as under Moreau–Jean θ = ½. (Weighted like a force,
// hβ/γ, it would drift by h²(β/γ − ½)|friction|/m a step: first order.)
//
// With c_w = (1 − α_f)/(1 − α_m) and S = M + hγc_w C + h²βc_w K (the iteration matrix, factored by
// StructuralOperators), eliminating ẅ_{n+1} gives v_{n+1} = v_free + G P with v_free the step
// without contacts and
//   G = S⁻¹ (M + c K) M⁻¹ Hᵀ,   c = h² c_w (β − γ/2) ≥ 0,
//   W = H G = H S⁻¹ Hᵀ + c H S⁻¹ K M⁻¹ Hᵀ.
// With proportional damping (Rayleigh, C = a M + b K, or none) M, C and K share their modes Φ
// (ΦᵀMΦ = I, ΦᵀKΦ = Ω²), and W = H Φ diag((1 + cω²)/(1 + h²βc_w ω² + hγc_w(a + bω²))) Φᵀ Hᵀ: symmetric and
// positive, the same kind of operator as Moreau–Jean's, solved by the same PGS. Damping that does not
// share the modes (two damped bodies, or springs on a damped one) would make W nonsymmetric: refused. Then
//   q_{n+1} = q_free + Σ r_a [h(½ − β/γ) Z_a + (hβ/γ) G_a],   ẅ_{n+1} = ẅ_free + Σ r_a (G_a − Z_a)/(hγc_w),
// with Z_a = M⁻¹ h_aᵀ. The columns Z and G of a row are kept by its identity while S and the row stay
// (a finite-element node resting or sliding on a plane).
//
// Limit: the positions differ from the trapezoid of the velocities by h²(β − γ/2)(a_{n+1} − a_n).
// On a smooth motion that is O(h³), but at a contact node of a stiff body a holds the node's share of
// the contact force (the contacts are out of the recursion), so that each change of the contact forces
// moves the contact nodes by that much without a velocity to show it: the elastic shoe's error at a
// large step grows with the mesh and as ρ∞ falls (docs/generalized-alpha.md; 0 at ρ∞ = 1).
//
// Contacts: detected at q_n within the travel of the free step; active when the gap closes over half
// the free step, g + ½ H (q_free − q_n) ≤ ε (ε: the stage's touching band; Moreau–Jean's rule at
// θ = ½); Newton's impact law u_n⁺ ≥ −e u_n⁻ on the normal rows, and an inelastic contact still open by its gap closes it within
// the step (Stewart & Trinkle's term, with q_{n+1} − q_free ≈ ½ h (v_{n+1} − v_free), exact at ρ∞ = 1).
//
// Energy: no closed discrete balance is known for this scheme with contacts. The stepper keeps the
// kinetic and elastic energies, the work of loads (trapezoidal), the impulses' −Σ r hΔq/h and the
// damping's, and calls numerical dissipation what closes the balance: the energy the scheme removed
// (≥ 0 when it creates none). A check of the balance itself could not fail, and is not evaluated.
//
// Not handled, refused before the first step (unsupported()): finite-strain bodies (the step would
// need Newton's loop), 3D rigid bodies (rotations need a Lie-group generalized-α), linear constraints,
// prescribed components, ties, and damping that does not share the modes of M and K.
#pragma once

#include "engine/contact_stage/contact_stage.h"
#include "engine/dynamics.h"
#include "engine/mass_solver.h"
#include "engine/structural_operators.h"
#include "engine/steppers/generalized_alpha_parameters.h"
#include "engine/steppers/generalized_alpha_response.h"
#include "engine/steppers/phase_clock.h"
#include "engine/steppers/stepper.h"
#include "engine/world.h"

#include <memory>
#include <string>

namespace csim {

class GeneralizedAlpha final : public Stepper {
 public:
  GeneralizedAlpha(const World& world, const GeneralizedAlphaParameters& parameters);

  // "" when the World can be run, else why not and what to use instead.
  static std::string unsupported(const World& world);

  void initialize(State& state) override;
  void step(State& state) override;
  void summarize_settings(SummaryEntries& out) const override;

 private:
  std::unique_ptr<IterationOperator> make_response();
  void free_step(const State& state);
  void detect(const State& state);
  void assemble(const State& state);
  void update();
  void account_energy(State& state);

  const World& world_;
  GeneralizedAlphaParameters parameters_;
  GeneralizedAlphaCoefficients coefficients_;
  Dynamics dynamics_;
  StructuralOperators operators_;
  MassSolver mass_;
  GeneralizedAlphaResponse* response_ = nullptr;  // the stage's operator (the jumps of update())
  ContactStage stage_;
  PhaseClock clock_;

  Vector acceleration_, recursion_;  // ẅ_n and a_n
  Vector a_star_, v_hat_, q_hat_, f_loads_start_, f_loads_end_, f_total_, work_, work2_;
  Vector w_free_, v_free_, q_free_, w_next_, a_next_, v_next_, q_next_;
};

}  // namespace csim
