// The quasi-static stepper: incremental loading without inertia, with the same frictional contact
// solve as Moreau–Jean, on the tangent stiffness instead of the iteration matrix.
//
// A load step from t_k to t_{k+1} (a pseudo-time: the loads' multipliers λ(t), the prescribed
// displacements and the friction ramp give the loading path). The unknowns are z, the coordinates
// that are neither prescribed nor tied (reduced_coordinates.h: q = Φ(z, t)). Starting from the
// predictor z_k + (h_{k+1}/h_k) Δz_k (Δz_k the last accepted step's increment of z, h_k its length; z_k
// alone at the first step and when the unknowns change) with the prescribed components at t_{k+1},
// Newton's method solves the equilibrium
//   Tᵀ (f(q) + Hᵀ r) = 0,   f = loads − internal forces (N),  r the contact forces (N),
// each iteration j being a linearized frictional contact problem at q_j:
//   stiffness  K_z = Tᵀ K_T(q_j) T + ties' geometric term (held positive definite, see below);
//   detect     contacts whose gap is ≤ integrator.contact_distance at q_j, their frames and rows H
//              (H_z = H T), through the contact stage (contact_stage.h) with the stiffness as its
//              iteration operator (quasi_static_operator.h);
//   problem    u = W r + b,  W = H_z K_z⁻¹ H_zᵀ,  b = H_z K_z⁻¹ Tᵀ f + c:
//              on the normal row c = g_j, so that u_n = g_j + H_n Δq is the gap at the end of the
//              iteration (Signorini at the position level); on the tangential rows c = H_t (q_j − q_k),
//              so that u_t is the slip over the whole step, on which Coulomb's law acts (Δq: the
//              increment of the iteration; the ground's own motion is in q through its prescribed
//              coordinates);
//   update     Δz = K_z⁻¹ Tᵀ(f + Hᵀ r),  z_{j+1} = z_j + ω_j Δz,  q_{j+1} = Φ(z_{j+1}, t_{k+1}),
//              ω_j = 1 unless the iteration oscillates (then a secant under-relaxation) or creeps at a
//              steady linear rate (then Aitken's extrapolation; secant_relaxation.h);
// until |Δz|∞ ≤ newton_tolerance · L (L: the largest body's bounding radius, m; angles count as
// lengths on a unit arm), or, on modified Newton's iterates (below), until the bound θ/(1−θ) |Δz|∞ on
// the distance to the equilibrium that their observed contraction θ gives is (kept_factor.h). A World
// of linear bodies without ties takes one iteration, its contact geometry linearized at q_k (small
// displacements), as the stepper always did. For the others, a step whose Newton does not converge in
// newton_max_iterations (or meets an inverted element, or ends on a failed contact solve) is taken
// again as two half steps, each halved again if it fails, down to
// max_cutbacks halvings (counted in the summary); only then does the run stop (exit 2). The
// loading path being a function of t, a half step is a load step like any other; the step's outputs
// (velocities Δq/h, impulses) stay those of the whole step. The predictor only moves the first iterate
// (steady rolling repeats its increments); q_k stays the step start of the slip rows. A step that does
// not converge with the predictor and modified Newton (below) is first taken again with neither, from
// z_k with a factor at every iterate, before it is halved: they change the path of the iterates, and no
// step that Newton's own iteration converges is halved for them.
//
// Modified Newton. An iterate keeps the factor of the step's last factored one, and then evaluates the
// forces without the tangent, while that factor holds the same rows (the same contacts, held the same
// way) with the same weights (held_weight_, hub_proximal_ below), and while each iterate that kept it
// shrank |Δz|∞ by KeptFactor::kContraction at least (kept_factor.h); otherwise, or when its solve lets
// a held row go or fails, the iterate factors its own tangent. The residual f, the rows H, their offsets
// and the Delassus operator W = H A⁻¹ Hᵀ are the iterate's own with the kept A, and the held rows' load
// −ρ H_Aᵀ c_A takes the kept ρ and the iterate's rows: at a fixed point (Δz = 0, the held rows held,
// c_A = 0) the equilibrium holds as with Newton's own matrix; the rate is linear instead of quadratic
// (counted in the summary as kept_factor_iterations).
//
// Holding K_z positive definite. The Delassus operator needs K_z positive definite, which the
// equilibrium with its contacts does not guarantee:
//   a rigid body carrying a tied ring (a hub) free to turn has no stiffness of its own: the ring's
//   rigid rotation is held only by friction (and by nothing in a frictionless press);
//   a stressed body held by contacts can have an indefinite tangent on its own (a compressed ring's
//   sway: the initial-stress term, which the contacts balance).
// First remedy, the held rows: the contacts the warm start holds (closed: r_n > 0; sticking: their
// tangential rows too) give A = K_z + ρ H_Aᵀ H_A, with the load Tᵀf − ρ H_Aᵀ c_A. Both sides gain
// ρ H_Aᵀ (H_A Δz + c_A) = ρ H_Aᵀ u_A, zero while those rows stay held (u_n = 0, u_t = 0), so the step is
// Newton's own. A row that the solve lets go (a contact that opens, or slips) is dropped and the
// problem solved again (at most 4 times; the rare step still inexact costs an iteration, not the
// converged state, since a fixed point holds its rows). ρ = 1e-4, 1e-3, … ×
// max diag(K_z) until A is positive definite; a contact solve that fails on held rows is solved again
// with ρ from 100 times more (up to max diag, kept for the step's later iterates): the held rows' sticking
// contacts can be coupled to the nearly free spin so that μ|W_nt| ≈ W_nn, which Gauss–Seidel does not
// finish, and a stiffer hold shrinks W along those rows without changing the step while they stay held. With a hub, the held rows need a sticking contact, and the
// frame's geometric stiffness then takes the contact forces too (the exact Hessian): Newton converges
// quadratically while rolling (measurements: docs/quasi-static-history.md).
// Otherwise (no contact sticks: the whole patch slips in the spin-up), the proximal terms: ε =
// 1e-4 · max diag(K_z) on the hub's unknowns, and, when K_z is still not positive definite, ε on every
// unknown from 1e-6 · max diag(K_z), grown tenfold until it is (counted in the summary as regularized
// iterations; the held rows' as contact_held). Proximal terms are springs from the last iterate: they
// vanish at convergence (Δz = 0), so the converged state is unbiased, but they slow Newton to a linear
// rate along the modes they hold. The hub's term starts each step at 1e-4, between a value that leaves
// the contact solves ill-conditioned and one that slows Newton (docs/quasi-static-history.md). A
// contact solve that fails with it raises it ×100 (up
// to max diag) for the rest of the step: with a nearly free spin the problem can have no solution
// (quasi_static.cpp, solve_contact_problem). Without the held rows, the frame's geometric stiffness
// takes the loads and internal forces only: with the contact forces, the rigid rotation of a pressed
// wheel gets −N (R − δ) (its nodes leave the ground), which nothing then balances.
//
// Penalty friction (a contact law's elastic_slip γ > 0, Abaqus' "allowable elastic slip"). A sticking
// contact may slip elastically by γ·φ, φ = r_t/(μ r_n) the mobilized fraction of its cone, so that
// it reaches the friction limit after a slip γ, whatever its normal force (Abaqus scales the penalty
// with the pressure the same way). Over a step from φ_k, stick becomes
//   ũ_t = u_t + γ (r_t/(μ r_n) − φ_k) = 0,
// and slip is Coulomb's law on ũ_t (the elastic part recovered, the rest dissipated): the same problem
// with W_tt + γ/(μ r_n) on the diagonal and −γ φ_k in b, which PGS solves unchanged. r_n is first the
// warm start's, then the solve's own: the problem is solved again at the new normal forces until they
// settle (a few passes; a contact without a normal force gets no friction). Held sticking rows hold
// ũ_t, not u_t (their offset takes γ/(μ r_n) r_t at the warm start), so a fixed point stays unbiased.
//
// Soft directions. A rigid-body mode held only by a spring of negligible stiffness (or by none, with a
// pivot left at round-off of either sign) factors, but W = H_z K_z⁻¹ H_zᵀ is then (1/k) a aᵀ plus the
// body's compliance: when k is below round-off of the body's stiffness the compliance is lost in W's
// entries and b's (a Hertz contact on a quarter disk held by k = 1e-3 N/m with E = 2e11 Pa put the whole
// load on one node: +1175 % on the peak pressure, with a contact residual of 1e-13, measured relative
// to |b| ≈ P/k). The decision is made on the factor's pivots, whatever their sign: an unknown j whose
// pivot D_j ≤ 1e-10 K_jj (K holds that direction by less than 1e-10 of its own stiffness) gets a proximal
// term ε = 1e-6 K_jj, factored again until no pivot is small (a few rounds: the term at one node may
// not reach a mode that does not move it). The proximal term is a spring from the last iterate: it
// vanishes at the fixed point Δz = 0, so the converged state is the one without it, and W is conditioned
// by 1e6 instead of 1/k (3 or 4 iterates a step on the quarter disk; 7 with 1e-4). Such a factor is
// iterated to Newton's tolerance in a linear World too, with the step start's contact geometry (the
// offsets shifted by H_z Δz); when the contacts do not hold the mode (a loaded body whose contact opens),
// the iterates do not converge and the run stops, naming the node and component of the small pivot
// (exit 2). When they do converge, the accepted iterate must show that something holds the mode: K_z with its closed contacts'
// rows (ρ H_Aᵀ H_A, ρ = max diag K_z: normal rows, and tangential ones where the contact sticks) must have
// no small pivot; otherwise the mode is unloaded and free (a free rotation the load does not turn), its
// position the proximal terms' choice, and the run stops the same way. So the decision no longer depends
// on the sign or size of a pivot left by round-off, which differed from one mesh to another. Counted as
// regularized iterations.
//
// Complementarity. The accepted iterate's contacts must meet Signorini's law on the configuration it
// reaches, u = c + H_z Δz formed from Δz rather than through W: its penetration −u_n, and the gap u_n
// of a contact that carries a normal force (as min(u_n, r_n / max r_n · L)), at most failure_residual · L
// (m); otherwise the step fails with a message naming the contact law, the gap and the force. The contact
// solver's own residual is relative to |b|, which a soft direction makes as large as the motion it
// allows; this one is in metres. summary.json gives its largest value over the accepted iterates
// (complementarity.max_violation, m) beside its tolerance.
//
// Outputs: state velocities hold Δq / h, impulses r·h (so that contact-force probes read r), the
// contacts' points and gaps at the end of the step (the converged configuration: detected at the last
// iterate, then carried by its increment, ContactDetector::move_contact, so that a closed contact's gap
// is the one its solve made ≈ 0); state.reactions the generalized force each prescription exerts (N, N·m);
// Newton's counters.
#pragma once

#include "engine/contact_stage/contact_stage.h"
#include "engine/dynamics.h"
#include "engine/linear_algebra/sparse_ldlt.h"
#include "engine/reduced_coordinates.h"
#include "engine/steppers/kept_factor.h"
#include "engine/steppers/phase_clock.h"
#include "engine/steppers/quasi_static_operator.h"
#include "engine/steppers/quasi_static_parameters.h"
#include "engine/steppers/secant_relaxation.h"
#include "engine/steppers/stepper.h"

#include <string>

namespace csim {

class QuasiStatic final : public Stepper {
 public:
  QuasiStatic(const World& world, const QuasiStaticParameters& parameters);

  // What of the World this stepper cannot take, as a message naming it and what to use instead; empty
  // when it can run the World (checked by the scene loader before the first step).
  static std::string unsupported(const World& world);
  static std::string unsupported(const World& world, const ReducedCoordinates& reduced);  // its bodies' part

  void initialize(State& state) override;
  void step(State& state) override;
  void measure_energy(State& state) const override;  // the elastic energy at state.q
  void summarize_statistics(const State& state, SummaryEntries& out) const override;
  bool tracks_energy_balance() const override { return false; }  // the elastic energy only

 private:
  void advance(State& state, double t_next, int halvings);
  // accelerated: with the predictor and modified Newton (as parameters_ allow), else Newton's plain iteration.
  std::string solve_increment(const State& state, double t_next, bool accelerated);
  void accept(State& state, double t_next);
  // One Newton iteration at q_j (state.q at the step start is q_k); returns |Δz|∞.
  double iterate(const State& state, double t_next);
  // The iterate's contact problem on its factored stiffness, or on the kept factor while keep (which turns
  // false when the kept factor cannot serve), solved in rounds; returns whether held rows were used.
  bool solve_contact_problem(double t_next, bool& keep);
  void assemble_stiffness(const Vector& q, std::size_t world_from);
  bool factor_stiffness();
  bool hold_soft_directions();  // proximal terms on the directions K_z does not hold (see the header)
  std::string describe_unknown(int unknown) const;
  std::string soft_directions() const;
  void shift_contact_offsets(const State& state);  // a linear World's later iterates
  void measure_complementarity();
  std::string complementarity_failure(double t_next);  // of the accepted iterate (see the header)
  std::string unheld_directions(double t_next);  // soft directions the closed contacts do not hold either
  bool release_let_go_rows();
  void update_contact_force();  // contact_force_ ← Hᵀ r
  void add_row_product(int a, double scale, Triplets& triplets);  // scale · h_aᵀ h_a, h_a row a of H_z
  void detect_contacts(const State& state, double t_next);
  void soften_friction(const State& state);  // penalty friction's terms (see the header)
  double set_compliance(const Vector& r);
  void assemble_problem();
  // f; with tangent, the bodies' tangent into triplets_ too (when needs_tangent()).
  std::size_t generalized_force(const Vector& q, double t, Vector& f, bool tangent);
  std::unique_ptr<IterationOperator> make_operator();
  bool needs_tangent() const { return !(linear_ && factored_); }  // a linear World's is factored once

  // A pivot D_j ≤ this × K_jj: a direction that K does not hold (see the header).
  static constexpr double kSingularPivot = 1e-10;

  const World& world_;
  QuasiStaticParameters parameters_;
  Dynamics dynamics_;
  ReducedCoordinates reduced_;
  double reduced_time_ = 0.0;  // s, the time whose prescriptions reduced_ holds
  bool linear_;                 // constant K, no ties: one iteration, one factorization
  bool factored_ = false;
  SparseLdlt factor_;
  SparseRowMatrix T_;
  // The contact stage (contact_stage.h) over the stiffness: detection, rows H_z = H T, W, the solves.
  QuasiStaticOperator* operator_ = nullptr;  // the stage's, which it owns (set by make_operator)
  ContactStage stage_;
  SparseMatrix K_z_;
  SparseMatrix held_matrix_;   // K_z + G + ρ HᵀH, on K_z's pattern when it holds them (factor_stiffness)
  Vector held_values_, geometric_values_, base_values_;  // HᵀH, G and K_z + G over K_z's values
  Triplets triplets_;  // the bodies' tangents (finite-strain floating ones first, in their hub's frame), then the springs'
  double contact_distance_, length_;
  double t_ = 0.0;  // the time the current step reaches (s), for messages
  int d_;

  Vector z_, q_, f_, f_z_, f_aug_, dz_, reactions_;
  Vector q_detected_;          // the iterate's q that the stage's contacts and rows were detected at
  Vector offset_;              // c: the contacts' gaps (normal rows) and slips since q_k (tangential rows)
  Vector compliance_;          // penalty friction: γ/(μ r_n) on tangential rows (m/N), else 0
  Vector start_impulse_;       // the contacts' impulses at the step start (penalty friction's φ_k)
  Vector compliance_normal_;   // the normal forces compliance_ was set at (N)
  bool penalty_friction_ = false;
  Vector contact_force_;       // Hᵀ r (N, N·m), in velocity components
  SecantRelaxation relaxation_;  // Newton's step length ω (secant_relaxation.h)
  // Phase times (phase_clock.h), every iteration of every step, failed ones included: free_velocity
  // holds the forces, tangent and its factorization (the free increment K⁻¹ f), assembly the Delassus
  // operator and the warm start, solve the contact solves, update the rest of the iteration.
  PhaseClock clock_;
  PhaseTimers timers_;
  double held_weight_ = 0.0;   // the held rows' least ρ this step's iterates start from (/ max diag)
  double hub_proximal_ = 0.0;  // the hub's proximal weight this step's iterates start from (/ max diag)
  std::string contact_failure_;  // the last iterate's contact solve failure message, or ""
  Vector step_increment_;      // q_j ⊖ q_k in velocity components (m, rad): the slip rows' argument
  // The predictor (see the header): Σ ω Δz over this attempt's iterates, its predicted part included, and
  // the last accepted step's sum with that step's length (s); empty when there is none or the unknowns
  // changed since.
  Vector z_increment_, last_z_increment_;
  bool accelerated_ = true;    // this attempt's: predictor and modified Newton (solve_increment)
  double last_step_length_ = 0.0;
  SolverCounters* counters_ = nullptr;
  std::vector<ActiveContact> previous_;  // the last iterate's contacts with their forces (the warm start)
  std::vector<ContactStatus> warm_status_;  // the warm start's statuses of the stage's contacts
  std::vector<Hold> hold_;     // per contact of the stage, the rows held (kept_factor.h)
  // Modified Newton (see the header): the step's last factor, what it was made with.
  KeptFactor kept_;
  double held_rho_ = 0.0;      // the ρ of factor_stiffness' last held factor (N/m)
  KeptFactor::Kind factor_kind_ = KeptFactor::Kind::stiffness;  // … and what it factored
  bool factor_regularized_ = false;                             // … with grown proximal terms
  // The unknowns of z whose pivot was small (hold_soft_directions), which the factor holds by proximal
  // terms; empty when it holds none.
  std::vector<int> soft_unknowns_;
  SparseLdlt hold_check_;  // K_z with the closed contacts' rows (unheld_directions)
  std::vector<int> row_unknowns_;  // add_row_product's scratch
  int iteration_ = 0;  // of the current attempt (solve_increment)
  // The last iterate's violation of Signorini's law (measure_complementarity): m, the contact (index in
  // the stage's, −1 for none), its gap (m) and normal force (N).
  double complementarity_ = 0.0, complementarity_gap_ = 0.0, complementarity_force_ = 0.0;
  int complementarity_contact_ = -1;
  double max_complementarity_ = 0.0;  // m, the largest complementarity_ of an accepted iterate (the summary's)
  HeldRows held_rows() const;  // hold_ with its contacts' keys
  Vector held_load() const;    // H_Aᵀ c̃_A over the held rows (ρ times it leaves the load with them)
};

}  // namespace csim
