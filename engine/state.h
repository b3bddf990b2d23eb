// The mutable part of a simulation: time, coordinates, the contact set of the last step (its impulses
// are the next step's warm start, matched by contact key), solver counters, the energy balance and
// per-phase timers.
#pragma once

#include "contact/coulomb_local.h"
#include "contact/contact_point.h"
#include "engine/bodies/body.h"

#include <algorithm>
#include <string>
#include <vector>

namespace csim {

// One active contact of the last step. impulse = (r_n, r_t1, r_t2) in N·s over the step, in the frame
// of `point` (normal from the law's body A to body B).
struct ActiveContact {
  ContactPoint point;
  int law = -1;
  int body_a = -1, body_b = -1;  // bodies of the point's objects A and B
  Eigen::Vector3d impulse = Eigen::Vector3d::Zero();
  ContactStatus status = ContactStatus::open;
};

struct SolverCounters {
  long steps = 0;
  long solves = 0;                // steps with a non-empty contact problem
  long total_iterations = 0;      // PGS sweeps, summed
  int max_iterations = 0;
  long not_converged = 0;         // solves whose residual stayed above the tolerance
  double max_residual = 0.0;      // worst final residual over the run (relative)
  double first_not_converged_time = -1.0;  // s
  long rejected_local_solutions = 0;
  long contact_points = 0;        // active contacts, summed over steps
  int max_contact_points = 0;
  // m: the largest overlap (−gap) of an active contact at the configuration a step starts from (the
  // gaps its detection measured), 0 if none overlapped: how far bodies interpenetrate over the run.
  double deepest_penetration = 0.0;
  // A step's contact set into the three figures above.
  void count_contacts(const std::vector<ActiveContact>& contacts) {
    contact_points += static_cast<long>(contacts.size());
    max_contact_points = std::max(max_contact_points, static_cast<int>(contacts.size()));
    for (const ActiveContact& c : contacts) deepest_penetration = std::max(deepest_penetration, -c.point.gap);
  }
  long newton_iterations = 0;     // Newton iterations (quasi-static; Moreau–Jean with finite-strain bodies), summed over steps
  int max_newton_iterations = 0;  // the most in one step
  long newton_regularized = 0;    // iterations whose tangent needed a proximal term to be positive definite
  long newton_held = 0;           // iterations whose tangent was held by its contacts' rows instead (quasi_static.h)
  long newton_kept_factor = 0;    // quasi-static: iterations that solved with an earlier iterate's factor (modified Newton)
  long newton_relaxed = 0;        // iterations whose step the secant model lengthened or shortened (secant_relaxation.h)
  long newton_backtracks = 0;     // Moreau–Jean: iterates taken again on a shorter step after an element inverted
  long newton_redetections = 0;   // Moreau–Jean: steps whose Newton moved farther than their contact detection reached
  long newton_activated_contacts = 0;  // Moreau–Jean: contacts activated by Newton's motion, not the prediction
  int bodies_asleep = 0;          // Moreau–Jean with sleeping bodies: asleep after the last step
  long detections_retaken = 0;    // Moreau–Jean in two halves: steps whose motion outran their detection's margin
  long sparse_solves = 0;         // Moreau–Jean: solves whose W was stored sparse by blocks (contact_stage.h)
  long dense_fallbacks = 0;       // of those, solved again stored dense (contact_solve.h)
  long sweeps_only_retries = 0;   // solves then taken again by the sweeps alone, from zero (contact_solve.h)
  long cold_restarts = 0;         // solves taken again from r = 0 after failing from their warm start (contact_solve.h)
  long max_delassus_entries = 0;  // the most entries of W stored by a solve (m² dense, the nonzeros sparse)
  long cutbacks = 0;              // quasi-static load steps taken again as two halves after Newton failed
};

// Energy bookkeeping (J), accumulated from t = 0. The discrete balance of the θ-method,
//   ΔE_kinetic + ΔE_elastic = W_loads − D_contact − D_numerical,
// holds to solver tolerance for linear springs (see moreau_jean.h for the derivation);
// D_numerical = (θ − ½)(|Δv|²_M + |Δq|²_K) ≥ 0 is the θ-method's own dissipation.
struct EnergyBalance {
  double kinetic = 0.0, elastic = 0.0;            // current values
  double initial_kinetic = 0.0, initial_elastic = 0.0;
  double work_of_loads = 0.0;                     // loads, gravity and inertial forces
  double contact_dissipation = 0.0;               // −Σ rᵀ H v_θ (contacts and constraints)
  double numerical_dissipation = 0.0;
  double damping_dissipation = 0.0;               // h Σ v_θᵀ C v_θ (Rayleigh damping)
  double sleep_dissipation = 0.0;                 // kinetic energy of bodies put to sleep (Moreau–Jean)
  double max_abs_residual = 0.0;                  // worst |balance| over the run
  double residual() const {
    return kinetic + elastic - initial_kinetic - initial_elastic - work_of_loads + contact_dissipation +
           numerical_dissipation + damping_dissipation + sleep_dissipation;
  }
};

// Statistics of the smooth integrator (SUNDIALS IDA), zero for the others.
struct IdaStatistics {
  std::string linear_solver;            // dense or klu
  long steps = 0;                       // internal steps
  long residual_evaluations = 0;
  long jacobian_evaluations = 0;
  long error_test_failures = 0;
  long nonlinear_convergence_failures = 0;
  long symbolic_analyses = 0;           // KLU's symbolic analyses of the Jacobian's pattern (klu only)
  double last_step = 0.0;               // s
  std::vector<double> penalty_stiffness, penalty_damping;  // N/m, N·s/m per contact law (ida)
};

// s, wall clock, summed over steps (steppers/phase_clock.h: a linear Moreau–Jean run estimates them from
// one step in 16; Newton steppers time every iteration). Quasi-static: free_velocity holds the forces,
// the tangent and its factorization, assembly the Delassus operator.
struct PhaseTimers {
  double free_velocity = 0.0, detection = 0.0, assembly = 0.0, solve = 0.0, update = 0.0;
};

// A state reached exactly at an event of an event-driven integrator (a stick/slip switch), inside the
// last step: the run samples the probes there too.
struct EventSample {
  double t = 0.0;  // s
  Vector q, v;
};

struct State {
  double t = 0.0;  // s
  Vector q, v;
  std::vector<EventSample> events;      // events inside the last step, in time order
  std::vector<ActiveContact> contacts;  // sorted by key
  Vector reactions;                     // generalized force of each prescribed component (N, N·m), else 0
  SolverCounters counters;
  EnergyBalance energy;
  IdaStatistics ida;
  PhaseTimers timers;
  double factorization_seconds = 0.0;   // s, the iteration matrix's (re)factorizations, in total
};

}  // namespace csim
