// The keys a study sets in its cases (csim stress's sweep keys, csim sweep's --set-list, --grid and sweeps
// files) are checked once, before the first case: a key that `--set` could not replace would fail every
// case alike, each as a "bad input" row, where the study itself is the bad input (exit 2). A value the
// scene rejects stays the failure of its own case.
#pragma once

#include "engine/steppers/integrator.h"

#include <optional>
#include <string>

namespace csim {

struct Scene;

// Why `key` cannot be set in a case run by `integrator` on `scene` (the scene loaded with every override
// the cases share, so that its tree holds every default: load_scene), or nothing when it can. The rule
// is the loader's (integrator_keys.h, load_scene): an integrator's own key (integrator.rtol) must be
// read by the case's integrator; any other key must name a single value of the effective configuration
// (not a section, not a list).
std::optional<std::string> case_key_problem(const Scene& scene, const std::string& key, Integrator integrator);

}  // namespace csim
