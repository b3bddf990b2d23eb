// The parameters of the IDA integrator (ida_integrator.h), apart from the integrator so that the scene
// settings can hold them without SUNDIALS' and the stepper's dependencies.
#pragma once

#include <string>

namespace csim {

// What only the IDA integrators read (the scene keys integrator.rtol, atol, penalty_stiffness, ...).
struct IdaOptions {
  double rtol = 1e-6;              // relative tolerance
  double atol = 1e-8;              // absolute tolerance (units of the unknowns: m, m/s, J)
  double penalty_stiffness = 0.0;  // N/m; 0 = the default of ida_integrator.h
  double penalty_damping = -1.0;   // N·s/m; < 0 = from each law's restitution
  double epsilon = 1e-6;           // m/s
  std::string linear_solver = "auto";
  double max_step = 0.0;           // s, bound on IDA's steps; 0 = none for ida, the sample step for ida-events
  long max_steps = 1000000;        // internal steps over the run
};

struct IdaParameters : IdaOptions {
  double sample_step = 1e-3;       // s, interval between probe samples
  bool events = false;             // ida-events: exact Coulomb with located stick/slip events
};

}  // namespace csim
