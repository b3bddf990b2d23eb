// The Moreau–Jean θ-method for nonsmooth contact dynamics (M. Jean, CMAME 1999; Acary & Brogliato,
// Numerical Methods for Nonsmooth Dynamical Systems, 2008, ch. 10).
//
// One step from t_k to t_{k+1} = t_k + h, in the order of docs/architecture.md §2, with the iteration
// matrix A = M + hθC + h²θ²K (structural_operators.h, factored once when K is constant):
//   1. free velocity   A (v_free − v_k) = h [θ f(t_{k+1}) + (1−θ) f(t_k) + f_int(q_k) − θ h K v_k − C v_k];
//   2. detect          candidates within twice the step's travel. A linear step with close_gaps makes
//                      every candidate of an inelastic law (e = 0) a row: its condition below is
//                      g(q_{k+1}) ≥ 0 linearized, which an open contact that the step does not close meets
//                      with r = 0, so a row costs a sweep's reading and nothing else; a contact that a
//                      neighbour's impulse pushes shut within the step is then held by the same solve (a
//                      rule that activated on a prediction missed those, and each miss cost a second
//                      solve: a 1000-sphere drop took 2.3 solves a step and 3.3 times as long, bench_drop).
//                      Otherwise (e > 0, close_gaps = false, the Newton step) a contact is active when its
//                      predicted gap g + γ h u_n ≤ ε (γ = ½), u_n from the θ-weighted free velocity
//                      (1−θ)v_k + θ v_free, ε the stage's touching band (1e-9 of the World's size,
//                      contact_stage.h);
//   3. assemble        the contact stage (contact_stage.h) forms W = H A⁻¹ Hᵀ through A's operator
//                      (iteration_operator.h) and b = H v_free, to which the step adds Newton's impact law
//                      e·u_n(v_k) on normal rows and, on an inelastic contact (e = 0) whose gap g is still
//                      open, (g + h(1−θ)u_n(v_k))⁺ / (hθ), so that its condition is g(q_{k+1}) ≥ 0 and it
//                      stops on the surface (Stewart & Trinkle, IJNME 1996, on open gaps only; a gap within
//                      ε counts as 0; close_gaps = false: the textbook u_n(v_{k+1}) ≥ 0). Then the rows of the linear constraints and of
//                      the prescribed components (world.h; their force, impulse / h, is state.reactions),
//                      whose target makes them hold exactly in position at t_{k+1}, and those of the ties
//                      (tie_rows.h), linearized at each iterate, which hold at Newton's convergence;
//   4. solve           projected Gauss–Seidel on {W, b, μ}, warm-started by contact key;
//   5. update          v_{k+1} = v_free + A⁻¹ Hᵀ r,  q_{k+1} = q_k + h((1−θ) v_k + θ v_{k+1});
//   6. post            energy balance, reactions, counters, non-finite check; then, when asked for, the
//                      islands at rest put to sleep (sleeping_islands.h: an asleep body keeps v = 0 and
//                      its position, takes no part in steps 2–5, and is woken before step 3 by a contact
//                      with a moving body, the detection then taken again). A linear World only.
//
// Two halves. A sparse linear World (no finite-strain body, prescription or tie) takes the solves of
// steps 1 and 5 in two halves, so that a step reads the factor L twice, not three times
// (forward_columns.h): step 1 stops at w = L⁻¹ P h f, z = D⁻¹ w; each row's H v_free = H v_k + y_hᵀ z from
// its forward column y_h = L⁻¹ P hᵀ (every candidate's, for step 2's rule); step 5 is
// v_{k+1} = v_k + Pᵀ L⁻ᵀ D⁻¹ (w + Y r). Step 2's margin then covers twice the travel of the faster of v_k
// and the last step's v_θ; a step whose motion went farther is taken again with v_free formed whole
// (SolverCounters::detections_retaken), so that no contact the motion closes is left undetected. A World
// of rigid bodies and point masses alone (A block diagonal by body) takes the same two halves through its
// body-block operator (body_block_operator.h): no forward column, A⁻¹ applied body by body.
//
// Finite-strain bodies (nonlinear internal force f(q), tangent K_T(q)): the step is the implicit
//   M (v_{k+1} − v_k) = h [f_loads + θ f(q_{k+1}) + (1−θ) f(q_k) − C v_θ] + Hᵀ r,
//   q_{k+1} = q_k + h v_θ,
// solved by Newton's method on v_{k+1} with the contact problem inside every iteration (Acary &
// Brogliato 2008, §10.4; Siconos' MoreauJeanOSI): at the iterate v_j, q_j = q_k + h((1−θ)v_k + θv_j),
//   A_j = M + hθC + h²θ² K_T(q_j),   v_free = v_j − A_j⁻¹ R(v_j)   (R: the equation above without Hᵀ r),
// then steps 3–5 with A_j give v_{j+1}. The contacts are detected once, at q_k (the predicted-gap
// rule of step 2 with the first free velocity), and their rows kept for the step, as in the linear
// scheme. Stops at h |v_{j+1} − v_j|∞ ≤ newton_tolerance · L (L: the largest body's bounding radius).
// The prediction can miss what the converged step does, so at convergence:
//   - a candidate that the rule of step 2 activates with Newton's v_θ in place of the prediction is
//     activated, and the iterations go on (a node arriving in a rolling patch faster than predicted
//     would otherwise cross the surface unseen; measured on the ring of docs/rolling.md, 34 × 5);
//   - a step that moved a point farther than the detection's margin is taken again, detected over its
//     own motion (at most twice; then the run stops and says so).
// Along the way a step may be lengthened or shortened by the secant model of the last two
// (secant_relaxation.h: A_j + ε I, the proximal term of structural_operators.h, holds a nearly free
// spin too stiffly, and Newton creeps), and a step after which an element inverts is halved.
// The first iteration from v_0 = v_k is the linear scheme above (f(q_k + h v_k) − f(q_k) = −hK v_k for
// a linear body), so a linear World keeps its single solve. The energy balance then closes to the
// trapezoidal rule's error on the path integral of f, O(|Δq|³) a step (second order in h).
//
// Energy: with v_θ = (1−θ)v_k + θv_{k+1} and Δq = h v_θ, multiplying the step by v_θ gives exactly
//   ΔE_kin + ΔE_el = h f_loads·v_θ + rᵀ H v_θ − (θ−½)(|Δv|²_M + |Δq|²_K)
// for linear springs, so the bookkeeping in State closes to solver tolerance; θ > ½ dissipates. For a
// nonlinear force f the same product gives (θ−½)(|Δv|²_M − Δq·(f(q_{k+1}) − f(q_k))) in place of the
// last term, with ΔE_el taken by the trapezoidal rule: the balance closes to that rule's error.
#pragma once

#include "engine/contact_stage/contact_stage.h"
#include "engine/contact_stage/forward_columns.h"
#include "engine/dynamics.h"
#include "engine/structural_operators.h"
#include "engine/tie_rows.h"
#include "engine/steppers/moreau_jean_parameters.h"
#include "engine/steppers/phase_clock.h"
#include "engine/steppers/secant_relaxation.h"
#include "engine/steppers/sleeping_islands.h"
#include "engine/steppers/stepper.h"
#include "engine/world.h"

#include <memory>

namespace csim {

class MoreauJean final : public Stepper {
 public:
  MoreauJean(const World& world, const MoreauJeanParameters& parameters);
  ~MoreauJean() override;

  void initialize(State& state) override;
  void step(State& state) override;
  void summarize_settings(SummaryEntries& out) const override;
  void summarize_statistics(const State& state, SummaryEntries& out) const override;
  const SleepingIslands& sleeping() const { return sleep_; }

 private:
  static constexpr double kActivationGamma = 0.5;  // γ of step 2's rule g + γ h u_n ≤ 0

  std::unique_ptr<IterationOperator> make_iteration();
  void build_equalities(double t);
  void linearize_ties(const State& state, const Vector& v_iterate);
  void compute_loads(const State& state);
  void compute_free_velocity(const State& state);
  void compute_newton_free_velocity(const State& state, const Vector& v_iterate);
  void check_free_velocity(const Vector& v_free, double t) const;
  void step_newton(State& state);
  int newton_iterations(State& state);
  void detect_solve_update(State& state);  // steps 2–5 of a linear step
  void step_in_two_halves(State& state);   // a sparse linear World, after its forward half (see the header)
  void detect(const State& state);
  double detection_margin(const State& state);
  int activate_closed_by_motion(double time);
  void assemble(const State& state);
  double equality_target(const State& state, int e) const;
  void update(State& state);
  void integrate_positions(const Vector& q, const Vector& v_theta, Vector& out) const;
  void account_energy(State& state);
  void finish_step(State& state);
  void settle(State& state);
  // A large World with a constant K: K v_{k+1}, which the energy balance forms, is the next step's
  // K v_k while v is the one this stepper left and K has not been refactored (one product with K a step
  // instead of two).
  bool keeps_stiffness_velocity() const;
  bool stiffness_velocity_kept(const Vector& v) const;

  const World& world_;
  MoreauJeanParameters parameters_;
  Dynamics dynamics_;
  StructuralOperators operators_;
  // The ties' rows after the constraints', linearized at each iterate; tie_targets_: the velocities
  // C v_{k+1} that close their gaps at t_{k+1}.
  TieRows ties_;
  bool two_halves_;                          // whether this World takes them (see the header)
  TwoHalvesOperator* halves_ = nullptr;  // the stage's operator of A, in two halves
  ContactStage stage_;
  SleepingIslands sleep_;             // bodies at rest asleep (sleeping_islands.h); off unless asked for
  double length_;                     // m: Newton's length scale (World::length_scale)
  double detection_margin_ = 0.0;     // m: the last detection's margin
  Vector reach_velocity_;             // Newton: a converged v_θ that outran the detection, which then covers it
  EqualityRows equalities_;           // the World's constraints, then the active prescriptions (dynamics.h)
  Vector tie_targets_, q_tie_rows_;

  // Per-step work data (kept to avoid allocation in the time loop).
  Vector f_start_, f_iterate_, v_iterate_, q_iterate_;  // Newton: f(q_k), f(q_j), v_j, q_j
  Vector newton_step_;                // Newton: v_{j+1} − v_j, before its relaxation
  SecantRelaxation relaxation_;       // Newton: the length of its step (secant_relaxation.h)
  PhaseClock clock_;                  // State::timers (phase_clock.h)
  Vector stiffness_velocity_, stiffness_velocity_next_, kept_velocity_;  // K v_k, K v_{k+1}, the v_k kept
  Vector mass_velocity_;              // M v_{k+1} of a sparse linear World (account_energy)
  long kept_factorization_ = -1;      // operators_.factorizations() when K v was kept
  Vector f_loads_, f_total_, v_free_, v_predicted_, v_next_, v_theta_, q_next_, dv_, work_;
  // Two halves: whether this step formed v_free (a retake), and the travel its detection's margin covers (m).
  bool free_velocity_formed_ = false;
  double reach_ = 0.0;
};

}  // namespace csim
