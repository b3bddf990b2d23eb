#include "engine/steppers/sleeping_islands.h"

#include <algorithm>
#include <numeric>

namespace csim {

namespace {

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

SleepingIslands::SleepingIslands(const World& world, const SleepParameters& parameters)
    : world_(world), parameters_(parameters) {
  const int nb = static_cast<int>(world.bodies.size());
  may_sleep_.assign(nb, 0);
  asleep_.assign(nb, 0);
  quiet_time_.assign(nb, 0.0);
  island_of_.assign(nb, -1);
  if (!enabled()) return;
  for (int i = 0; i < nb; ++i) {
    const Body& body = *world.bodies[i].body;
    may_sleep_[i] = !body.fixed() && !body.elastic() && !body.nonlinear();
  }
  // Whatever acts on a body besides its contacts and gravity keeps it awake.
  for (const Spring& s : world.springs) {
    if (s.body_a >= 0) may_sleep_[s.body_a] = 0;
    if (s.body_b >= 0) may_sleep_[s.body_b] = 0;
  }
  for (const Load& l : world.loads) may_sleep_[l.body] = 0;
  for (const PrescribedComponent& p : world.prescribed) may_sleep_[p.body] = 0;
  for (const RigidTie& t : world.ties) may_sleep_[t.rigid_body] = may_sleep_[t.elastic_body] = 0;
  for (const LinearConstraint& c : world.constraints)
    for (const auto& [index, coefficient] : c.terms)
      for (int i = 0; i < nb; ++i) {
        const BodyInstance& b = world.bodies[i];
        if (index >= b.velocity_offset && index < b.velocity_offset + b.body->velocity_size()) may_sleep_[i] = 0;
      }
}

bool SleepingIslands::wake_touched(const std::vector<ActiveContact>& candidates) {
  if (asleep_count_ == 0) return false;
  bool woke = false;
  for (const ActiveContact& c : candidates) {
    const int a = c.body_a, b = c.body_b;
    const bool asleep_a = asleep_[a] != 0, asleep_b = asleep_[b] != 0;
    if (asleep_a == asleep_b) continue;  // both awake, or both asleep (the filter keeps none of those)
    const int sleeper = asleep_a ? a : b, other = asleep_a ? b : a;
    if (world_.bodies[other].body->fixed()) continue;
    wake(island_of_[sleeper]);
    woke = true;
  }
  return woke;
}

void SleepingIslands::wake(int island) {
  if (island < 0) return;  // already woken by an earlier candidate
  Island& s = islands_[island];
  for (int body : s.bodies) {
    asleep_[body] = 0;
    quiet_time_[body] = 0.0;
    island_of_[body] = -1;
    --asleep_count_;
  }
  s.bodies.clear();
  s.contacts.clear();  // the last step's list still holds them: the warm start reads them there
  kept_changed_ = true;
  ++woken_;
}

void SleepingIslands::hold_velocities(Vector& v_next) const {
  if (asleep_count_ == 0) return;
  for (std::size_t i = 0; i < asleep_.size(); ++i) {
    if (!asleep_[i]) continue;
    const BodyInstance& b = world_.bodies[i];
    v_next.segment(b.velocity_offset, b.body->velocity_size()).setZero();
  }
}

void SleepingIslands::hold_positions(const Vector& q, Vector& q_next) const {
  if (asleep_count_ == 0) return;
  for (std::size_t i = 0; i < asleep_.size(); ++i) {
    if (!asleep_[i]) continue;
    const BodyInstance& b = world_.bodies[i];
    q_next.segment(b.position_offset, b.body->position_size()) = q.segment(b.position_offset, b.body->position_size());
  }
}

bool SleepingIslands::settle(double h, double t, std::vector<ActiveContact>& contacts, Vector& v) {
  const int nb = static_cast<int>(asleep_.size());
  for (int i = 0; i < nb; ++i) {
    if (!may_sleep_[i] || asleep_[i]) continue;
    quiet_time_[i] = world_.bodies[i].point_speed_bound(v, world_.dimension) <= parameters_.speed ? quiet_time_[i] + h : 0.0;
  }
  // Islands of the awake moving bodies over this step's contacts (the asleep ones' kept contacts are
  // not among them: they were not detected), and the bodies that keep theirs awake.
  parent_.resize(nb);
  std::iota(parent_.begin(), parent_.end(), 0);
  blocked_.assign(nb, 0);
  for (const ActiveContact& c : contacts) {
    const bool fixed_a = world_.bodies[c.body_a].body->fixed(), fixed_b = world_.bodies[c.body_b].body->fixed();
    if (!fixed_a && !fixed_b) parent_[find_root(parent_, c.body_a)] = find_root(parent_, c.body_b);
    const ContactLaw& law = world_.contact_laws[c.law];
    if (law.mu_ramp_end > law.mu_ramp_start && t < law.mu_ramp_end) blocked_[fixed_a ? c.body_b : c.body_a] = 1;
  }
  for (int i = 0; i < nb; ++i)
    if (!world_.bodies[i].body->fixed() && (!may_sleep_[i] || quiet_time_[i] < parameters_.time)) blocked_[i] = 1;
  for (int i = 0; i < nb; ++i)
    if (blocked_[i]) blocked_[find_root(parent_, i)] = 1;
  // The islands that fall asleep: one entry of islands_ per root, bodies ascending.
  new_island_.assign(nb, -1);
  bool any = false;
  for (int i = 0; i < nb; ++i) {
    if (world_.bodies[i].body->fixed() || asleep_[i]) continue;
    const int root = find_root(parent_, i);
    if (blocked_[root]) continue;
    if (new_island_[root] < 0) {
      auto free = std::find_if(islands_.begin(), islands_.end(), [](const Island& s) { return s.bodies.empty(); });
      if (free == islands_.end()) free = islands_.insert(islands_.end(), Island{});
      new_island_[root] = static_cast<int>(free - islands_.begin());
      ++slept_;
      any = true;
    }
    const int s = new_island_[root];
    islands_[s].bodies.push_back(i);
    island_of_[i] = s;
    asleep_[i] = 1;
    ++asleep_count_;
    const BodyInstance& b = world_.bodies[i];
    v.segment(b.velocity_offset, b.body->velocity_size()).setZero();
  }
  if (any) {  // the newly asleep islands' contacts move into their keeping
    std::size_t awake = 0;
    for (ActiveContact& c : contacts) {
      const int body = world_.bodies[c.body_a].body->fixed() ? c.body_b : c.body_a;
      if (asleep_[body]) islands_[island_of_[body]].contacts.push_back(c);
      else contacts[awake++] = c;
    }
    contacts.resize(awake);
  }
  if (any || kept_changed_) gather_kept();
  if (!kept_.empty()) {
    merged_.clear();
    merged_.reserve(contacts.size() + kept_.size());
    std::merge(contacts.begin(), contacts.end(), kept_.begin(), kept_.end(), std::back_inserter(merged_),
               [](const ActiveContact& x, const ActiveContact& y) { return x.point.key < y.point.key; });
    contacts.swap(merged_);
  }
  return any;
}

// Every asleep island's contacts in one list, in key order (rebuilt when an island sleeps or wakes).
void SleepingIslands::gather_kept() {
  kept_.clear();
  for (const Island& s : islands_) kept_.insert(kept_.end(), s.contacts.begin(), s.contacts.end());
  std::sort(kept_.begin(), kept_.end(),
            [](const ActiveContact& x, const ActiveContact& y) { return x.point.key < y.point.key; });
  kept_changed_ = false;
}

}  // namespace csim
