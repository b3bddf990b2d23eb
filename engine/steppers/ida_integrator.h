// The smooth reference integrator: SUNDIALS IDA (variable-order, variable-step BDF) on the residual
//   F(t, y, y') = 0,   y = (q, w, W_loads, D_contact, D_damping):
//     q' − Q(q) N w                                  = 0   positions (Q: quaternion rate in 3D)
//     NᵀM N w' − Nᵀ (f(t, q, v) + f_contact(q, v))   = 0   momentum, v = N w
//     W_loads' − f_loads·v                           = 0   work of loads (energy bookkeeping)
//     D_contact' + f_contact·v                       = 0   work done against the contacts
//     D_damping' + f_damping·v                       = 0   energy dissipated by viscous damping (when damped)
// with f = f_loads + f_internal + f_damping the smooth stage of dynamics.h (loads, gravity, gyroscopic
// terms, springs, linear and finite-strain internal forces, Rayleigh damping), N an orthonormal basis of
// the null space of the linear constraints C (eliminated, not enforced by multipliers: C v = C N w = 0
// holds identically; only for Worlds small enough for a dense N), and f_contact from the regularized
// contact law of contact/regularized_law.h at every contact point with a negative gap. The energy in
// the penalty springs, Σ ½ k g², is counted as elastic energy (and taken out of D_contact, which is
// then what friction and the penalty dashpots dissipated), so that the balance closes to IDA's tolerance.
//
// Settings (scene keys integrator.*): rtol, atol (IDA's scalar tolerances), penalty_stiffness (N/m; 0:
// per contact law, see regularized_contact_model.h: 1e8 × the heaviest mass for lumped bodies, and
// kPenaltyRatio × the stiffest node of an elastic body in contact), penalty_damping (N·s/m; default from
// each contact law's restitution), epsilon (m/s, the regularization velocity of Coulomb's law, default
// 1e-6), linear_solver (dense, klu or auto: KLU above 100 unknowns), max_step (s, a bound on IDA's step;
// by default none for ida and one sample interval for ida-events, whose extrema must be exact),
// max_steps (IDA's internal steps over the whole run: a budget, past which the run stops with a clear
// message rather than crawling).
//
// Jacobian: the dense solver (small lumped Worlds) uses IDA's internal difference quotients. KLU gets
// an assembled sparse Jacobian, cj NᵀMN + ∂F/∂y from the smooth stage's tangents (K, C and the
// gyroscopic term), the contact law's derivatives on the contact rows (differences of the local law,
// the rotation of the contact frame left out) and the quaternion rates of 3D rigid bodies (differences
// per body); the energy rows keep their diagonal only (they feed nothing back, so Newton still
// converges). KLU must never refactor a pattern it has not analysed: the Jacobian is stored on the
// union of every pattern seen so far (entries that vanish stay as explicit zeros), and when a new
// contact grows that union the symbolic analysis is redone (SUNLinSol_KLUReInit), counted in the
// summary as symbolic_analyses. A node in contact with a rigid plane adds entries to its own block
// only: on the elastic shoe the pattern grows once, when friction first couples a node's normal and
// tangential velocities (which the consistent mass matrix does not).
//
// ida-events (parameters.events): no regularization; the contact forces are the reactions of exact
// Coulomb friction whose stick/slip mode switches at events located by IDA's root finding (see
// event_contact_model.h for the model and its scope). Each event is handed to the run as an exact
// sample (State::events), so that extrema at stops are measured where they happen.
//
// Initial conditions are consistent by construction: y'(0) is computed from the equations (w' from
// the momentum balance), so no IDACalcIC is needed. The probes are sampled every time.step (IDA
// interpolates to the sample times; the sample interval does not limit IDA's own steps).
#pragma once

#include "engine/dynamics.h"
#include "engine/steppers/ida_parameters.h"
#include "engine/steppers/smooth_contact_model.h"
#include "engine/steppers/stepper.h"
#include "engine/world.h"

#include <Eigen/SparseCholesky>
#include <string>

namespace csim {

class IdaIntegrator final : public Stepper {
 public:
  IdaIntegrator(const World& world, const IdaParameters& parameters);
  ~IdaIntegrator() override;

  // What of the World this integrator cannot take, as a message naming it and what to use instead;
  // empty when it can run the World. The scene loader refuses such a scene before the first step.
  static std::string unsupported(const World& world, const IdaParameters& parameters);

  void initialize(State& state) override;
  void step(State& state) override;
  void summarize_statistics(const State& state, SummaryEntries& out) const override;

  // For the C callbacks of SUNDIALS.
  int residual(double t, const double* y, const double* y_rate, double* r);
  int event_functions(double t, const double* y, const double* y_rate, double* g);
  int sparse_jacobian(double t, double cj, const double* y, const double* y_rate, void* sparse_matrix);
  void record_error(const std::string& message) { last_error_ = message; }

 private:
  struct Sundials;  // SUNContext, IDA memory, vectors, matrix, linear solver

  // f at (t, q, v) into f_total_, with its loads and damping parts (dynamics.h).
  void smooth_forces(double t, const Vector& q, const Vector& v);
  void unpack(const double* y);            // q_, v_ from y
  void consistent_rates(double t);         // y' of the equations at the current y (in sundials_)
  void fill_state(State& state);
  IdaStatistics counters_since_restart() const;
  void apply_reduced_mass(const Eigen::Ref<const Vector>& w_rate, Eigen::Ref<Vector> out) const;  // NᵀMN w'
  Vector solve_reduced_mass(const Vector& b) const;  // (NᵀMN)⁻¹ b

  const World& world_;
  IdaParameters parameters_;
  Dynamics dynamics_;
  std::unique_ptr<SmoothContactModel> contact_model_;
  const class RegularizedContactModel* regularized_ = nullptr;  // contact_model_ when regularized
  Matrix null_basis_, reduced_mass_;         // N, NᵀMN (constrained Worlds, dense)
  Eigen::LDLT<Matrix> reduced_mass_factor_;
  Eigen::SimplicialLDLT<SparseMatrix> mass_factor_;  // unconstrained Worlds: M
  bool constrained_ = false;
  bool damped_ = false;                      // y has the damping's energy row
  int nq_, nv_, nr_, size_;                  // sizes of q, v, w and y
  std::unique_ptr<Sundials> sundials_;
  std::string last_error_;
  long sample_ = 0;
  long symbolic_analyses_ = 0;
  double initial_stored_energy_ = 0.0;    // J, in the penalty springs at t = 0
  IdaStatistics before_restart_;           // counters of the phases before the last event

  // Work data of the residual and the Jacobian.
  Vector q_, v_, w_rate_, q_rate_, f_loads_, f_damping_, f_total_, f_contact_;
  SparseMatrix jacobian_pattern_;          // the union of the Jacobian's patterns so far (values unused)
  Triplets jacobian_triplets_;
};

}  // namespace csim
