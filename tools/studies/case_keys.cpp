#include "tools/studies/case_keys.h"

#include "tools/scene/integrator_keys.h"
#include "tools/scene/scene.h"

namespace csim {

namespace {

// Whether a dotted key names a single value of the effective configuration (defaults included).
bool names_a_value(const YAML::Node& root, const std::string& key) {
  YAML::Node node = root;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    const std::string part = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (!node.IsMap() || !node[part].IsDefined()) return false;
    if (dot == std::string::npos) return node[part].IsScalar();
    node.reset(node[part]);
    start = dot + 1;
  }
}

}  // namespace

std::optional<std::string> case_key_problem(const Scene& scene, const std::string& key, Integrator integrator) {
  const std::string prefix = "integrator.";
  if (key.rfind(prefix, 0) == 0 && is_integrator_key(key.substr(prefix.size()))) {
    if (integrator_reads(integrator, key.substr(prefix.size()))) return std::nullopt;
    return "'" + key + "' is not a setting of the integrator " + integrator_name(integrator) +
           ", which the case runs (see csim dump-config --set integrator.type=" + integrator_name(integrator) + ")";
  }
  if (names_a_value(scene.document.root, key)) return std::nullopt;
  return "'" + key + "' is not a single value of the scene " + scene.document.file + " (see csim dump-config)";
}

}  // namespace csim
