// Which contact law governs a pair of bodies, when laws name bodies or groups (world.h).
//
// Precedence: the more specific law wins,
//   two bodies  >  a body and a group  >  two groups,
// as MuJoCo's explicit <pair> overrides what its geoms' group defaults would give. Two laws of the
// same specificity never share a pair silently: two laws with the same sides are refused, and so are
// [a, G] and [b, H] with a in H and b in G (both pair a with b) unless a law [a, b] settles that pair.
// (A body belongs to at most one group, so two group × group laws with different sides share no pair.)
// Refusing rather than letting the later law win keeps a scene's meaning independent of the order of
// its YAML map entries, which YAML does not define.
//
// Storage, linear in bodies and laws: a groups × groups table of law indices (few groups), a hash map
// of the body × body laws and one of the body × group laws. No table over body pairs.
// A body that no law's side holds has no law with any body: it touches nothing.
#pragma once

#include "engine/world.h"

#include <cstdint>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace csim {

// Two laws that cover one pair at the same specificity (law: the later one, other: the earlier);
// bodies: the pair (−1, −1 when the two laws have the same sides).
struct ContactLawConflict : std::invalid_argument {
  ContactLawConflict(const std::string& what, int later, int earlier, int first_body, int second_body)
      : std::invalid_argument(what), law(later), other(earlier), body_a(first_body), body_b(second_body) {}
  int law, other;
  int body_a, body_b;
};

class ContactLawTable {
 public:
  // Throws ContactLawConflict (the laws' sides must name existing bodies and groups).
  explicit ContactLawTable(const World& world);

  // The law between bodies i and j (i ≠ j), −1 for none.
  int law(int i, int j) const;
  // The law between i and j among those that name a group (the one a body × body law overrides), −1 for none.
  int law_by_group(int i, int j) const;
  // The group × group law between i and j, −1 for none.
  int law_by_groups(int i, int j) const;
  // True when some law's side holds the body.
  bool in_some_law(int body) const { return in_some_law_[body] != 0; }

 private:
  static std::uint64_t key(int first, int second) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(first)) << 32) | static_cast<std::uint32_t>(second);
  }
  const World& world_;
  int groups_ = 0;
  std::vector<int> group_pair_;                     // group_i · groups + group_j → law or −1
  std::unordered_map<std::uint64_t, int> body_pair_;   // (lower body, higher body) → law
  std::unordered_map<std::uint64_t, int> body_group_;  // (body, group) → law
  std::vector<char> in_some_law_;
};

// The bodies a law's side holds: the body, or the group's bodies.
std::vector<int> side_bodies(const World& world, int body, int group);

}  // namespace csim
