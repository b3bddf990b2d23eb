// The smooth reference integrator: SUNDIALS IDA (variable-order, variable-step BDF) on the residual
//   F(t, y, y') = 0,   y = (q, w, W_loads, D_contact):
//     q' − Q(q) N w                                   = 0   positions (Q: quaternion rate in 3D)
//     N ᵀM N w' − Nᵀ (f(t, q, v) + f_contact(q, v))    = 0   momentum, v = N w
//     W_loads' − f_loads·v                             = 0   work of loads (energy bookkeeping)
//     D_contact' + f_contact·v                         = 0   energy dissipated by contact
// where N is an orthonormal basis of the null space of the linear constraints C (the constraints are
// eliminated, not enforced by multipliers: C v = N... = 0 holds identically), and f_contact comes from
// the regularized contact law of contact/regularized_law.h at every contact point with a negative gap.
//
// Settings (scene keys integrator.*): rtol, atol (IDA's scalar tolerances), penalty_stiffness (N/m;
// default 1e8 × the heaviest body's mass in kg, i.e. a contact frequency of 1e4 rad/s for it and a
// penetration of about 1e-7 m under its own weight), penalty_damping (N·s/m; default from each contact
// law's restitution: ζ with e = exp(−ζπ/√(1−ζ²)) on the pair's effective mass), epsilon (m/s, the
// regularization velocity of Coulomb's law, default 1e-6), linear_solver (dense, klu or auto: KLU above
// 100 unknowns), max_step (s, a bound on IDA's step; by default none for ida and one sample interval for
// ida-events, whose extrema must be exact), max_steps (IDA's internal steps over the whole run: a budget, past which the run
// stops with a clear message rather than crawling).
//
// Jacobian: the dense solver uses IDA's internal difference quotients; KLU gets a column-by-column
// finite-difference Jacobian of ours, stored sparse (one residual per unknown: right for lumped
// systems; FE bodies will supply an analytical one).
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

#include "engine/forces.h"
#include "engine/steppers/smooth_contact_model.h"
#include "engine/steppers/stepper.h"
#include "engine/world.h"

#include <string>

namespace csim {

struct IdaParameters {
  double sample_step = 1e-3;       // s, interval between probe samples
  double rtol = 1e-6;              // relative tolerance
  double atol = 1e-8;              // absolute tolerance (units of the unknowns: m, m/s, J)
  double penalty_stiffness = 0.0;  // N/m; 0 = the default above
  double penalty_damping = -1.0;   // N·s/m; < 0 = from each law's restitution
  double epsilon = 1e-6;           // m/s
  std::string linear_solver = "auto";
  bool events = false;             // ida-events: exact Coulomb with located stick/slip events
  double max_step = 0.0;           // s, bound on IDA's steps; 0 = none for ida, the sample step for ida-events
  long max_steps = 1000000;        // internal steps over the run
};

class IdaIntegrator final : public Stepper {
 public:
  IdaIntegrator(const World& world, const IdaParameters& parameters);
  ~IdaIntegrator() override;

  void initialize(State& state) override;
  void step(State& state) override;
  double time_step() const override { return parameters_.sample_step; }

  // For the C callbacks of SUNDIALS.
  int residual(double t, const double* y, const double* y_rate, double* r);
  int event_functions(double t, const double* y, const double* y_rate, double* g);
  int finite_difference_jacobian(double t, double cj, const double* y, const double* y_rate,
                                 const double* r, void* sparse_matrix);
  void record_error(const std::string& message) { last_error_ = message; }

 private:
  struct Sundials;  // SUNContext, IDA memory, vectors, matrix, linear solver

  // Loads, inertial and spring forces at (t, q, v): f_loads_ (loads and inertial) and f_total_.
  void applied_forces(double t, const Vector& q, const Vector& v);
  void unpack(const double* y);            // q_, v_ from y
  void consistent_rates(double t);         // y' of the equations at the current y (in sundials_)
  void fill_state(State& state);
  IdaStatistics counters_since_restart() const;

  const World& world_;
  IdaParameters parameters_;
  ForceModel forces_;
  std::unique_ptr<SmoothContactModel> contact_model_;
  Matrix M_, null_basis_, reduced_mass_;     // M, N, NᵀMN
  Eigen::LDLT<Matrix> reduced_mass_factor_;
  bool constrained_ = false;
  int nq_, nv_, nr_, size_;                  // sizes of q, v, w and y
  std::unique_ptr<Sundials> sundials_;
  std::string last_error_;
  long sample_ = 0;
  IdaStatistics before_restart_;           // counters of the phases before the last event

  // Work data of the residual.
  Vector q_, v_, w_rate_, q_rate_, f_loads_, f_total_, f_contact_, body_rate_;
};

}  // namespace csim
