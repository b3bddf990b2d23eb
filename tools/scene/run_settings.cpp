// The parameters of each stepper, composed from the run settings (each held once there).
#include "tools/scene/scene.h"

namespace csim {

namespace {

// The step, contact-solver and Newton settings that Moreau–Jean and the quasi-static stepper both take.
template <class SteppingParameters>
void set_shared_settings(const RunSettings& run, SteppingParameters& parameters) {
  parameters.step = run.step;
  parameters.solver = run.contact_solver;
  parameters.failure_residual = run.failure_residual;
  parameters.newton_tolerance = run.newton.tolerance;
  parameters.newton_max_iterations = run.newton.max_iterations;
}

}  // namespace

MoreauJeanParameters moreau_jean_parameters(const RunSettings& run) {
  MoreauJeanParameters parameters;
  static_cast<MoreauJeanOptions&>(parameters) = run.moreau_jean;
  set_shared_settings(run, parameters);
  parameters.delassus_storage = run.delassus_storage;
  return parameters;
}

GeneralizedAlphaParameters generalized_alpha_parameters(const RunSettings& run) {
  GeneralizedAlphaParameters parameters;
  static_cast<GeneralizedAlphaOptions&>(parameters) = run.generalized_alpha;
  parameters.step = run.step;
  parameters.solver = run.contact_solver;
  parameters.failure_residual = run.failure_residual;
  parameters.delassus_storage = run.delassus_storage;
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
  set_shared_settings(run, parameters);
  parameters.delassus_storage = run.delassus_storage;
  return parameters;
}

}  // namespace csim
