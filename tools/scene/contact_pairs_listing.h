// Which bodies can touch, as `csim validate` lists them: a line per contact law with its two sides
// (bodies or groups), its μ and e, and the less specific laws it overrides (contact_law_table.h for
// the precedence), then the bodies that no law holds (they touch nothing). A group law is one line,
// not one per pair of its bodies.
#pragma once

#include "engine/world.h"

#include <string>

namespace csim {

std::string contact_pairs_listing(const World& world);

}  // namespace csim
