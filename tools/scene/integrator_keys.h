// Which integrator reads which key of a scene's `integrator` section, and the rule by which the scene
// loader refuses a key that the chosen integrator would ignore (exit 2 at load, so that csim validate
// and csim run give the same answer):
//   - a key given by --set integrator.KEY=... is refused unless the chosen integrator reads it;
//   - a key written in the file is refused unless the integrator the file declares (integrator.type as
//     written, moreau-jean when absent) or the chosen one reads it;
//   - a key written in the file for the file's own integrator, when --set integrator.type chose another
//     that ignores it, is dropped (no effect, and not in dump-config): csim compare and the integrator
//     matrix switch the integrator of every scene.
// integrator.type is read by every integrator. Keys outside this table are left to the strict reading
// (an unknown key is an error of its own).
#pragma once

#include "engine/steppers/integrator.h"

#include <optional>
#include <set>
#include <string>
#include <vector>

namespace csim {

// Every key the integrator section may hold: type, then the table's keys.
std::vector<std::string> integrator_section_keys();
// A key of the integrator section that some integrator reads (not type).
bool is_integrator_key(const std::string& key);
bool integrator_reads(Integrator integrator, const std::string& key);

// The integrator keys a scene was given, before --set and defaults are applied to its tree.
struct GivenIntegratorKeys {
  std::optional<Integrator> declared;  // integrator.type as written; moreau-jean when absent; none when unknown
  std::set<std::string> written;       // keys of the file's integrator section
  std::set<std::string> set;           // KEY of each --set integrator.KEY=...
};

}  // namespace csim
