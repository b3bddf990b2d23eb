#include "tools/scene/integrator_keys.h"

#include <vector>

namespace csim {

namespace {

struct KeyReaders {
  const char* key;
  std::vector<Integrator> readers;
};

const std::vector<KeyReaders>& key_table() {
  using enum Integrator;
  static const std::vector<KeyReaders> table{
      {"theta", {moreau_jean}},
      {"rtol", {ida, ida_events}},
      {"atol", {ida, ida_events}},
      {"penalty_stiffness", {ida, ida_events}},
      {"penalty_damping", {ida, ida_events}},
      {"epsilon", {ida, ida_events}},
      {"linear_solver", {ida, ida_events}},
      {"max_step", {ida, ida_events}},
      {"max_steps", {ida, ida_events}},
      {"contact_distance", {quasi_static}},
      {"newton_tolerance", {moreau_jean, quasi_static}},  // Moreau–Jean: finite-strain bodies
      {"newton_max_iterations", {moreau_jean, quasi_static}},
      {"max_cutbacks", {quasi_static}},
      {"close_gaps", {moreau_jean}},
      {"sleep_speed", {moreau_jean}},
      {"sleep_time", {moreau_jean}},
      {"rho_infinity", {generalized_alpha}},
  };
  return table;
}

}  // namespace

std::vector<std::string> integrator_section_keys() {
  std::vector<std::string> keys{"type"};
  for (const KeyReaders& entry : key_table()) keys.push_back(entry.key);
  return keys;
}

bool is_integrator_key(const std::string& key) {
  for (const KeyReaders& entry : key_table())
    if (key == entry.key) return true;
  return false;
}

bool integrator_reads(Integrator integrator, const std::string& key) {
  if (key == "type") return true;
  for (const KeyReaders& entry : key_table())
    if (key == entry.key)
      for (Integrator reader : entry.readers)
        if (reader == integrator) return true;
  return false;
}

}  // namespace csim
