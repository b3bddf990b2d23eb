// The parameters of each stepper, composed from the run settings (each held once there).
#include "tools/scene/scene.h"

namespace csim {

MoreauJeanParameters moreau_jean_parameters(const RunSettings& run) {
  MoreauJeanParameters parameters;
  static_cast<MoreauJeanOptions&>(parameters) = run.moreau_jean;
  parameters.step = run.step;
  parameters.solver = run.contact_solver;
  parameters.failure_residual = run.failure_residual;
  parameters.newton_tolerance = run.newton.tolerance;
  parameters.newton_max_iterations = run.newton.max_iterations;
  return parameters;
}

IdaParameters ida_parameters(const RunSettings& run) {
  IdaParameters parameters;
  static_cast<IdaOptions&>(parameters) = run.ida;
  parameters.sample_step = run.step;
  parameters.events = run.integrator == Integrator::ida_events;
  return parameters;
}

QuasiStaticParameters quasi_static_parameters(const RunSettings& run) {
  QuasiStaticParameters parameters;
  static_cast<QuasiStaticOptions&>(parameters) = run.quasi_static;
  parameters.step = run.step;
  parameters.solver = run.contact_solver;
  parameters.failure_residual = run.failure_residual;
  parameters.newton_tolerance = run.newton.tolerance;
  parameters.newton_max_iterations = run.newton.max_iterations;
  return parameters;
}

}  // namespace csim
