#include "engine/steppers/integrator.h"

namespace csim {

std::string integrator_name(Integrator integrator) {
  switch (integrator) {
    case Integrator::moreau_jean: return "moreau-jean";
    case Integrator::quasi_static: return "quasi-static";
    case Integrator::ida: return "ida";
    case Integrator::ida_events: return "ida-events";
    case Integrator::generalized_alpha: return "generalized-alpha";
  }
  return "unknown";
}

std::optional<Integrator> integrator_from_name(std::string_view name) {
  for (Integrator integrator : kIntegrators)
    if (integrator_name(integrator) == name) return integrator;
  return std::nullopt;
}

std::string integrator_names() {
  std::string names;
  for (Integrator integrator : kIntegrators) names += (names.empty() ? "" : ", ") + integrator_name(integrator);
  return names;
}

}  // namespace csim
