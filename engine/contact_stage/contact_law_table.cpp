#include "engine/contact_stage/contact_law_table.h"

#include <algorithm>

namespace csim {

std::vector<int> side_bodies(const World& world, int body, int group) {
  if (group >= 0) return world.groups[group].bodies;
  return {body};
}

ContactLawTable::ContactLawTable(const World& world)
    : world_(world), groups_(static_cast<int>(world.groups.size())) {
  group_pair_.assign(static_cast<std::size_t>(groups_) * groups_, -1);
  in_some_law_.assign(world.bodies.size(), 0);
  std::vector<char> group_marked(groups_, 0);
  const auto mark = [&](int body, int group) {
    if (body >= 0) in_some_law_[body] = 1;
    if (group < 0 || group_marked[group]) return;
    group_marked[group] = 1;
    for (int b : world.groups[group].bodies) in_some_law_[b] = 1;
  };
  const auto same_sides = [&](int later, int earlier) {
    return ContactLawConflict("the contact law '" + world.contact_laws[earlier].name + "' has the same sides", later,
                              earlier, -1, -1);
  };
  // The body × group laws whose body has a group, by (the body's group, the named group): the only
  // laws of one specificity that can share a pair.
  std::unordered_map<std::uint64_t, std::vector<std::pair<int, int>>> body_group_by_groups;  // → (body, law)
  const int laws = static_cast<int>(world.contact_laws.size());
  for (int l = 0; l < laws; ++l) {
    const ContactLaw& law = world.contact_laws[l];
    mark(law.body_a, law.group_a);
    mark(law.body_b, law.group_b);
    if (law.body_a >= 0 && law.body_b >= 0) {
      const auto [at, added] = body_pair_.emplace(key(std::min(law.body_a, law.body_b), std::max(law.body_a, law.body_b)), l);
      if (!added) throw same_sides(l, at->second);
    } else if (law.group_a >= 0 && law.group_b >= 0) {
      int& entry = group_pair_[static_cast<std::size_t>(law.group_a) * groups_ + law.group_b];
      if (entry >= 0) throw same_sides(l, entry);
      entry = group_pair_[static_cast<std::size_t>(law.group_b) * groups_ + law.group_a] = l;
    } else {
      const int body = law.body_a >= 0 ? law.body_a : law.body_b;
      const int group = law.group_a >= 0 ? law.group_a : law.group_b;
      const auto [at, added] = body_group_.emplace(key(body, group), l);
      if (!added) throw same_sides(l, at->second);
      if (world.bodies[body].group >= 0) body_group_by_groups[key(world.bodies[body].group, group)].emplace_back(body, l);
    }
  }
  // [a, G] and [b, H] with a in H and b in G both pair a with b. Each such pair needs a body × body
  // law, so that the work here is bounded by their number (laws in file order: the first conflict
  // found is the same on every run).
  for (int l = 0; l < laws && !body_group_by_groups.empty(); ++l) {
    const ContactLaw& law = world.contact_laws[l];
    if (law.between_bodies() || (law.group_a >= 0 && law.group_b >= 0)) continue;
    const int a = law.body_a >= 0 ? law.body_a : law.body_b;
    const int named = law.group_a >= 0 ? law.group_a : law.group_b;
    const int own = world.bodies[a].group;
    if (own < 0) continue;
    const auto partners = body_group_by_groups.find(key(named, own));
    if (partners == body_group_by_groups.end()) continue;
    for (const auto& [b, other] : partners->second) {
      if (b == a || body_pair_.count(key(std::min(a, b), std::max(a, b)))) continue;
      const int later = std::max(l, other), earlier = std::min(l, other);
      throw ContactLawConflict("the contact laws '" + world.contact_laws[earlier].name + "' and '" +
                                   world.contact_laws[later].name + "' both pair the bodies '" + world.bodies[a].name +
                                   "' and '" + world.bodies[b].name +
                                   "' (each names one of them and the other's group): add a law between these two "
                                   "bodies, which overrides both",
                               later, earlier, a, b);
    }
  }
}

int ContactLawTable::law(int i, int j) const {
  if (!body_pair_.empty()) {
    const auto found = body_pair_.find(key(std::min(i, j), std::max(i, j)));
    if (found != body_pair_.end()) return found->second;
  }
  return law_by_group(i, j);
}

int ContactLawTable::law_by_group(int i, int j) const {
  if (!body_group_.empty()) {
    const int group_i = world_.bodies[i].group, group_j = world_.bodies[j].group;
    if (group_j >= 0)
      if (const auto found = body_group_.find(key(i, group_j)); found != body_group_.end()) return found->second;
    if (group_i >= 0)
      if (const auto found = body_group_.find(key(j, group_i)); found != body_group_.end()) return found->second;
  }
  return law_by_groups(i, j);
}

int ContactLawTable::law_by_groups(int i, int j) const {
  const int group_i = world_.bodies[i].group, group_j = world_.bodies[j].group;
  if (group_i < 0 || group_j < 0) return -1;
  return group_pair_[static_cast<std::size_t>(group_i) * groups_ + group_j];
}

}  // namespace csim
