// The Moreau–Jean θ-method for nonsmooth contact dynamics (M. Jean, CMAME 1999; Acary & Brogliato,
// Numerical Methods for Nonsmooth Dynamical Systems, 2008, ch. 10).
//
// One step from t_k to t_{k+1} = t_k + h, in the order of docs/architecture.md §2:
//   1. free velocity   A (v_free − v_k) = h [θ f(t_{k+1}) + (1−θ) f(t_k) + f_int(q_k) − θ h K v_k]
//                      with the iteration matrix A = M + h²θ²K (factored once when K is constant);
//   2. detect          FCL broad + narrow phase; a contact is active when its predicted gap
//                      g + γ h u_n ≤ 0 (γ = ½), u_n from the θ-weighted free velocity
//                      (1−θ)v_k + θ v_free; warm start from the last impulse with the same key;
//   3. assemble        u = H v, Delassus W = H A⁻¹ Hᵀ, b = H v_free + e·u_n(v_k) on normal rows
//                      (Newton impact law); an inelastic contact (e = 0) whose gap g is still open
//                      adds (g + h(1−θ)u_n(v_k))⁺ / (hθ), so that its condition is g(q_{k+1}) ≥ 0 and
//                      it stops on the surface (Stewart & Trinkle, IJNME 1996, on open gaps only;
//                      close_gaps = false: the textbook u_n(v_{k+1}) ≥ 0, which holds a point caught
//                      by the activation rule up to γ h |u_n| above the surface). Then the rows of the
//                      linear constraints and of the prescribed components (world.h; their force,
//                      impulse / h, is state.reactions), whose target makes them hold exactly in
//                      position at t_{k+1}, and those of the ties (tie_rows.h), linearized at each
//                      iterate, which hold at Newton's convergence. H is sparse (a few entries a
//                      row). With a sparse A, W's entries are kept by row identity while A and the row
//                      do not change (a node sliding on a plane keeps its rows; delassus_cache.h), each
//                      row's from its forward column L⁻¹ P hᵀ, so that a step costs a solve, a
//                      backward substitution (step 5) and O(contacts²) once A is factored, and a row
//                      entering one sparse forward substitution;
//   4. solve           projected Gauss–Seidel on {W, b, μ};
//   5. update          v_{k+1} = v_free + A⁻¹ Hᵀ r,  q_{k+1} = q_k + h((1−θ) v_k + θ v_{k+1}); with a
//                      sparse A, A⁻¹ Hᵀ r = Pᵀ L⁻ᵀ D⁻¹ (Y r) from the kept forward columns Y of step 3;
//   6. post            energy balance, counters, non-finite check.
//
// A sparse linear World (no finite-strain body, prescription or tie) takes the solves of steps 1 and 5
// in two halves, so that a step reads the factor L twice, not three times (a large factor leaves the
// cache, and each pass over it is then bound by memory; docs/solver-measurements.md, sixth round):
//   1. w = L⁻¹ P h f (forward), z = D⁻¹ w; no v_free: each row's H v_free = H v_k + y_hᵀ z from its
//      forward column y_h = L⁻¹ P hᵀ, kept in the Delassus cache for every candidate (step 2's rule)
//      and every row of the problem (step 3's b), all the y_hᵀ z in one pass over the columns stored
//      by the factor's rows (forward_rows.h);
//   5. v_{k+1} = v_k + Pᵀ L⁻ᵀ D⁻¹ (w + Y r) (backward), w + Y r by the same rows.
// Step 2's margin, which v_free bounded, then covers twice the travel of the faster of v_k and the
// last step's v_θ; a step whose motion v_θ went farther is taken again with the margin of v_free,
// formed whole by one more backward pass (SolverCounters::detections_retaken), so that no contact the
// motion closes is left undetected. Every other World forms v_free whole.
//
// A lumped World (point masses, rigid bodies, springs) keeps its last detection (its candidates and
// their rows) and, for the same active contacts, equality rows and A⁻¹, its W, Hᵀ and A⁻¹ Hᵀ, while
// every coordinate of the moving bodies stays within 1/1024 of a unit of round-off of where it was
// detected (ContactDetector::positions_within: ε (|x| + the body's radius) a length, ε (|x| + 1) an angle
// or a quaternion entry) and the step's margin within the one it was detected with, twice that step's.
// A detection there would round to the same numbers but where an exact value lies that close to a
// rounding boundary, and then differ by an ulp: the kept one is the same to round-off. A body at rest
// costs no detection and no Delassus operator (incline-3d: the coordinates near zero move by about 1e-25
// a step, the others not at all); a candidate kept beyond the step's margin is not considered (the same
// set as a new detection). Only a World whose v_k travels less than that tolerance in a step (about
// 2e-19 of its length scale) remembers and compares: a moving one does none of it. SolverCounters::
// detections_kept counts the steps that kept their detection.
// A new detection whose Hᵀ is the last one to the bit, with the same A⁻¹, also keeps W and A⁻¹ Hᵀ (they
// are functions of them): a box sliding without turning (sdnv104-rigid), whose contacts' lever arms are
// its vertices' R r (ContactPoint::arm_a), not point − centre, whose rounding follows the position.
// SolverCounters::delassus_kept counts the steps with contacts that kept W either way.
// With W kept at rest, a contact problem whose b, μ and warm start are the last solved ones to the bit (a
// body at rest: sdnd100-a's pad once stopped, whose condensed problem takes Gauss–Seidel's slip scan at
// every step) takes that solve's impulses and statistics (SolverCounters::solves_repeated).
// Why a fraction of an ulp: kept over a few ulps of motion, a contact's gap, frozen or moved to first
// order, falls below what the coordinates resolve, and the closing term of step 3 then pushes at it at
// every step with a velocity the positions cannot follow (a block at rest on `incline` kept 4e-14 rad/s;
// bench/lumped_vs_bullet.md, tenth session).
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

#include "contact/pgs_solver.h"
#include "engine/contact_stage/contact_detector.h"
#include "engine/contact_stage/delassus_cache.h"
#include "engine/linear_algebra/forward_rows.h"
#include "engine/dynamics.h"
#include "engine/structural_operators.h"
#include "engine/tie_rows.h"
#include "engine/steppers/moreau_jean_parameters.h"
#include "engine/steppers/phase_clock.h"
#include "engine/steppers/secant_relaxation.h"
#include "engine/steppers/stepper.h"
#include "engine/world.h"

#include <map>
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

 private:
  void build_equalities(double t);
  void linearize_ties(const State& state, const Vector& v_iterate);
  int equality_count() const { return static_cast<int>(equalities_.rows.rows()) + ties_.size(); }
  double equality_dot(int e, const Vector& v) const;  // row e of the equalities (constraints, then ties) · v
  // Row a of the problem (its sparse contact rows, then the equalities) · v.
  double problem_row_dot(int a, const Vector& v) const;
  void compute_loads(const State& state);
  void compute_free_velocity(const State& state);
  void compute_newton_free_velocity(const State& state, const Vector& v_iterate);
  void check_free_velocity(const Vector& v_free, double t) const;
  void step_newton(State& state);
  void detect_solve_update(State& state);  // steps 2–5 of a linear step
  void step_in_two_halves(State& state);   // a sparse linear World, after its forward half (see the header)
  void gather_candidates();               // two halves: every candidate's rows and the equalities in the cache
  int candidate_row(int a) const;         // two halves: the candidate row of the problem's row a
  int equality_slot(int e);               // an equality row's slot in the Delassus cache
  int newton_iterations(State& state);
  void detect(const State& state);
  bool closes(std::size_t k, const Vector& v, double time) const;  // candidate k, predicted gap
  int activate_missed_contacts(double h);
  void activate_by_forward_columns(const State& state);  // two halves: step 2's rule without v_free
  // out += scale · (row a of the problem)ᵀ: the contacts' rows, then the equalities', then the ties'.
  template <class Dense>
  void add_problem_row(int a, double scale, Dense&& out) const;
  void gather_columns();
  void gather_delassus();
  void assemble(const State& state);
  void dense_delassus();  // W and G = A⁻¹ Hᵀ of a lumped World
  void solve(State& state, bool warm_from_state = true);
  void update(State& state);
  void integrate_positions(const Vector& q, const Vector& v_theta, Vector& out) const;
  void account_energy(State& state);
  // A large World with a constant K: K v_{k+1}, which the energy balance forms, is the next step's
  // K v_k, kept while v and K are the same to the bit (one product with K a step instead of two).
  bool keeps_stiffness_velocity() const;
  bool stiffness_velocity_kept(const Vector& v) const;

  const World& world_;
  MoreauJeanParameters parameters_;
  Dynamics dynamics_;
  StructuralOperators operators_;
  PgsSolver pgs_;
  ContactDetector detector_;
  int contact_dimension_;             // 2 in plane scenes, 3 in space
  double length_;                     // m: Newton's length scale (World::length_scale)
  double detection_margin_ = 0.0;     // m: the last detection's margin
  Vector reach_velocity_;             // Newton: a converged v_θ that outran the detection, which then covers it


  // Per-step work data (kept to avoid allocation in the time loop).
  Vector f_start_, f_iterate_, v_iterate_, q_iterate_;  // Newton: f(q_k), f(q_j), v_j, q_j
  Vector newton_step_;                // Newton: v_{j+1} − v_j, before its relaxation
  SecantRelaxation relaxation_;       // Newton: the length of its step (secant_relaxation.h)
  PhaseClock clock_;                  // State::timers (phase_clock.h)
  Vector stiffness_velocity_, stiffness_velocity_next_, kept_velocity_;  // K v_k, K v_{k+1}, the v_k kept
  Vector mass_velocity_;              // M v_{k+1} of a sparse linear World (account_energy)
  long kept_factorization_ = -1;      // operators_.factorizations() when K v was kept
  Vector f_loads_, f_total_, v_free_, v_predicted_, v_next_, v_theta_, q_next_, r_, dv_, work_, local_work_;
  std::vector<ContactStatus> statuses_;  // the contact solve's, kept to avoid allocation
  std::vector<ActiveContact> candidates_;
  std::vector<ActiveContact> active_;
  std::vector<SparseRow> candidate_rows_;  // rows of every candidate contact (dimension each)
  std::vector<int> active_rows_;      // candidate index of each active contact
  // Rows of the active contacts: candidate_rows_ of active_rows_, pointed at rather than copied (a
  // contact row is 188 bytes; incline-3d copied twelve a step).
  std::vector<const SparseRow*> rows_;
  // Small dense systems: A⁻¹ hᵀ for each row of the problem, the contacts' recomputed each step, the
  // constraints' once per factorization.
  std::vector<Vector> constraint_columns_;
  std::vector<Vector> direct_columns_;  // small elastic systems: recomputed each step, no cache
  long cache_factorization_ = -1;
  std::vector<const Vector*> columns_;                      // contact/constraint rows (m × n) and A⁻¹ Hᵀ
  // A sparse linear World: W kept by row identity (delassus_cache.h); each row's slot in it, and the
  // nonzeros of an equality row.
  DelassusCache delassus_cache_;
  std::vector<int> delassus_slots_, equality_index_;
  // The slots W was last copied from: while they still hold, W is not copied again (m² entries a step).
  DelassusCache::Taken copied_;
  std::vector<double> equality_value_;
  Vector forward_sum_;  // Y r, in the factor's order
  // Two halves (see the header): whether this World takes them, whether this step formed v_free (a
  // retake), the travel its detection's margin covers (m), w = L⁻¹ P h f and z = D⁻¹ w, and each
  // candidate row's slot (then the equalities').
  bool two_halves_ = false, free_velocity_formed_ = false;
  double reach_ = 0.0;
  Vector free_forward_, free_scaled_;
  std::vector<int> candidate_slots_;
  // The candidates' forward columns by the factor's rows (forward_rows.h); each candidate row's y_cᵀ z,
  // its h A⁻¹ f (a normal row's: u_n(v_free − v_k)); the impulses in candidate order, with the rows of the
  // problem marked, for w + Y r.
  ForwardRows forward_rows_;
  std::vector<double> candidate_dots_, candidate_impulses_;
  std::vector<char> candidate_in_problem_;
  FrictionContactProblem problem_;
  EqualityRows equalities_;           // the World's constraints, then the active prescriptions (dynamics.h)
  // The ties' rows after the constraints', linearized at each iterate, their A⁻¹ tᵀ recomputed
  // with them; tie_targets_: the velocities C v_{k+1} that close their gaps at t_{k+1}.
  TieRows ties_;
  std::vector<Vector> tie_columns_;
  Matrix problem_rows_;  // the problem's rows H (m × n), for a direct Delassus operator (structural_operators.h)
  Matrix problem_columns_, dense_columns_;  // a lumped World's Hᵀ and G = A⁻¹ Hᵀ (n × m each)
  Matrix fresh_columns_;                    // this step's Hᵀ, compared with the kept one before it replaces it
  // A lumped World's kept detection (see the header): whether v_k travels less than its tolerance in a
  // step (the bookkeeping is done only then), whether this step kept it, the margin it was made with
  // (m), and what W, Hᵀ and G were formed for (the active candidates, A's factorization count and the
  // equality rows' build count).
  bool at_rest_ = false, detection_kept_ = false;
  double kept_margin_ = -1.0;
  std::vector<int> delassus_rows_;
  long delassus_factorization_ = -1, delassus_equalities_ = -1, equalities_built_ = 0;
  bool delassus_kept_ = false;  // this step's W, Hᵀ and G are the last formed (the delassus_formed_-th)
  long delassus_formed_ = 0;
  // The last solve of a step that kept W, which a step may repeat: the W it had (delassus_formed_), its
  // b, μ and warm start, and its impulses, statuses and statistics.
  struct KeptSolve {
    long delassus = -1;
    Vector b, warm, r;
    std::vector<Eigen::Vector2d> mu;
    std::vector<ContactStatus> status;
    PgsStatistics statistics;
  } kept_solve_;
  Vector tie_targets_, q_tie_rows_;
};

}  // namespace csim
