#include "tools/scene/contact_pairs_listing.h"

#include "engine/contact_stage/contact_law_table.h"

#include <sstream>

namespace csim {

namespace {

std::string side_name(const World& world, int body, int group) {
  return group >= 0 ? "group " + world.groups[group].name : "body " + world.bodies[body].name;
}

// A body of the group other than `besides`, or −1.
int other_member(const World& world, int group, int besides) {
  for (int b : world.groups[group].bodies)
    if (b != besides) return b;
  return -1;
}

}  // namespace

std::string contact_pairs_listing(const World& world) {
  std::ostringstream out;
  if (world.contact_laws.empty()) return "contact laws: none (no body touches another)\n";
  const ContactLawTable table(world);
  out << "contact laws (a law naming two bodies overrides one naming a group; a body in no law touches nothing):\n";
  for (std::size_t l = 0; l < world.contact_laws.size(); ++l) {
    const ContactLaw& law = world.contact_laws[l];
    out << "  " << side_name(world, law.body_a, law.group_a) << " × " << side_name(world, law.body_b, law.group_b)
        << ": law " << law.name << " (";
    if (!law.collides) {
      out << "never collide";
    } else {
      out << "μ ";
      if (law.isotropic()) out << law.mu(0);
      else out << "[" << law.mu(0) << ", " << law.mu(1) << "]";
      out << ", e " << law.restitution;
    }
    // The law that this one replaces on its pairs, if any.
    int overridden = -1;
    if (law.between_bodies()) {
      overridden = table.law_by_group(law.body_a, law.body_b);
    } else if (law.group_a < 0 || law.group_b < 0) {
      const int body = law.body_a >= 0 ? law.body_a : law.body_b;
      const int other = other_member(world, law.group_a >= 0 ? law.group_a : law.group_b, body);
      if (other >= 0) overridden = table.law_by_groups(body, other);
    }
    if (overridden >= 0) out << "; overrides " << world.contact_laws[overridden].name;
    out << ")\n";
  }
  std::vector<std::string> untouched;
  for (std::size_t b = 0; b < world.bodies.size(); ++b)
    if (!table.in_some_law(static_cast<int>(b))) untouched.push_back(world.bodies[b].name);
  if (!untouched.empty()) {
    constexpr std::size_t kShown = 10;
    out << "bodies in no contact law (they touch nothing): " << untouched.size() << ":";
    for (std::size_t i = 0; i < untouched.size() && i < kShown; ++i) out << " " << untouched[i];
    if (untouched.size() > kShown) out << " ...";
    out << "\n";
  }
  return out.str();
}

}  // namespace csim
