// The parameters of the quasi-static stepper (quasi_static.h), apart from the stepper so that the scene
// settings can hold them without the stepper's dependencies.
#pragma once

#include "contact/pgs_solver.h"
#include "engine/contact_stage/iteration_operator.h"

namespace csim {

// What only the quasi-static stepper reads (the scene keys integrator.contact_distance, max_cutbacks).
struct QuasiStaticOptions {
  double contact_distance = 0.0;  // m; 0 = 10 % of the largest body's bounding radius
  int max_cutbacks = 4;           // halvings of a load step whose Newton fails, at most (h / 16)
};

struct QuasiStaticParameters : QuasiStaticOptions {
  double step = 0.1;              // s of pseudo-time per load step
  PgsParameters solver;
  double failure_residual = 1e-6;
  // contact_solver.storage: automatic or dense (the stepper's operator stores W dense; sparse is refused
  // when the scene is loaded).
  DelassusChoice delassus_storage = DelassusChoice::automatic;
  double newton_tolerance = 1e-10;  // on |Δz|∞ / L
  int newton_max_iterations = 30;
  // Newton's predictor and modified Newton (quasi_static.h), not scene keys: off only where a test compares
  // them with Newton's plain iteration.
  bool predictor = true;
  bool modified_newton = true;
};

}  // namespace csim
