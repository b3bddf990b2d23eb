// The time integrators a World can be run with, and their names (the scene key integrator.type, the
// "integrator" field of summary.json, csim compare's --integrators). The names are spelt here only.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace csim {

enum class Integrator {
  moreau_jean,   // "moreau-jean": the θ-method with nonsmooth contact (moreau_jean.h)
  quasi_static,  // "quasi-static": load steps without inertia (quasi_static.h)
  ida,           // "ida": SUNDIALS IDA on regularized contact (ida_integrator.h)
  ida_events,    // "ida-events": IDA with exact Coulomb friction and located stick/slip events
  generalized_alpha,  // "generalized-alpha": the nonsmooth generalized-α scheme (generalized_alpha.h)
};

inline constexpr Integrator kIntegrators[] = {Integrator::moreau_jean, Integrator::quasi_static, Integrator::ida,
                                              Integrator::ida_events, Integrator::generalized_alpha};

std::string integrator_name(Integrator integrator);
// The integrator of a name; nothing for an unknown name.
std::optional<Integrator> integrator_from_name(std::string_view name);
// "moreau-jean, quasi-static, ida, ida-events, generalized-alpha", for messages.
std::string integrator_names();

// The fixed-step nonsmooth schemes (Moreau–Jean, generalized-α): refined by their time step, their
// counters in State::counters.
inline bool is_time_stepping(Integrator integrator) {
  return integrator == Integrator::moreau_jean || integrator == Integrator::generalized_alpha;
}

// Both IDA variants (they share IdaParameters and IdaStatistics).
inline bool is_ida(Integrator integrator) {
  return integrator == Integrator::ida || integrator == Integrator::ida_events;
}

}  // namespace csim
