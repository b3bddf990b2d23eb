// The parameters of the Moreau–Jean stepper (moreau_jean.h), apart from the stepper so that the scene
// settings can hold them without the stepper's dependencies.
#pragma once

#include "contact/pgs_solver.h"
#include "engine/contact_stage/iteration_operator.h"
#include "engine/steppers/sleeping_islands.h"

namespace csim {

// What only Moreau–Jean reads (the scene keys integrator.theta, integrator.close_gaps).
struct MoreauJeanOptions {
  double theta = 0.5;             // θ ∈ [½, 1]
  bool close_gaps = true;         // inelastic contacts close their open gap within the step (step 3)
  SleepParameters sleep;          // integrator.sleep_speed, sleep_time (sleeping_islands.h); off by default
};

struct MoreauJeanParameters : MoreauJeanOptions {
  double step = 1e-3;             // h, s
  PgsParameters solver;
  double failure_residual = 1e-6; // a solve left above this relative residual stops the run
  DelassusChoice delassus_storage = DelassusChoice::automatic;  // contact_solver.storage
  double newton_tolerance = 1e-10;  // finite-strain bodies: on h |Δv|∞ / L
  int newton_max_iterations = 30;
  // A sparse linear World's solves in two halves around the contact solve (moreau_jean.h); false forms
  // v_free whole at every step (no scene key: the tests compare the two).
  bool two_halves = true;
};

}  // namespace csim
