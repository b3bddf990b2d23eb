// Bodies at rest put to sleep, and woken by a contact (Bullet's deactivation, MuJoCo's sleeping islands):
// the explicit mechanism by which a settled pile stops costing a step's detection and contact solve.
//
// Who may sleep: a moving rigid body or point mass that nothing but its contacts and gravity acts on (no
// spring end, load, constraint term, prescription or tie): its block of the iteration matrix A is its
// own, so that holding its velocity at zero changes no other body's free velocity. Other moving bodies
// (elastic, sprung, loaded, driven) never sleep, and neither does an island that holds one.
//
// The rule, after each step:
//   - a body is quiet when no point of it moves faster than `speed` (m/s): |v| + |ω| R ≤ speed, R its
//     bounding radius (BodyInstance::point_speed_bound); its quiet time grows by h, and is reset by a
//     step that is not quiet;
//   - islands: the moving bodies joined by the step's contacts (rows: touching or within the detection's
//     margin), fixed bodies joining nothing; an island falls asleep when every body in it has been quiet
//     for `time` (s), it holds no body that may not sleep, and none of its contacts' laws is ramping μ
//     (ContactLaw::mu_at changes after t);
//   - falling asleep sets its velocities to exactly zero (the kinetic energy removed is booked as
//     EnergyBalance::sleep_dissipation, so the balance still closes) and keeps its contacts with their
//     last impulses (a body at rest: its weight's share × h), which the contact probes read while it
//     sleeps and which warm-start its contacts when it wakes;
//   - while asleep, a body's velocity is zero and its position is held; the detection skips every pair of
//     two resting bodies (asleep or fixed), so an asleep island costs neither narrow phase nor rows;
//   - a detected contact between an asleep body and a moving awake one wakes the asleep body's island
//     before the contact problem is formed (the step's detection is then taken again), so a body
//     dropped on a sleeping pile meets a pile that responds.
#pragma once

#include "engine/state.h"
#include "engine/world.h"

#include <vector>

namespace csim {

struct SleepParameters {
  double speed = 0.0;  // m/s; 0: no body sleeps
  double time = 0.5;   // s
  bool enabled() const { return speed > 0.0; }
};

class SleepingIslands {
 public:
  SleepingIslands(const World& world, const SleepParameters& parameters);

  bool enabled() const { return parameters_.enabled(); }
  // Per body: 1 while asleep (the detector's filter reads it, ContactDetector::set_asleep).
  const std::vector<char>& asleep() const { return asleep_; }
  int asleep_count() const { return asleep_count_; }
  long islands_put_to_sleep() const { return slept_; }
  long islands_woken() const { return woken_; }

  // After a detection: wakes the island of every asleep body that a candidate joins to a moving awake
  // body. Returns whether any woke (the caller then detects again).
  bool wake_touched(const std::vector<ActiveContact>& candidates);

  // The asleep bodies' velocities set to zero, and their positions held (q_next's slice = q's).
  void hold_velocities(Vector& v_next) const;
  void hold_positions(const Vector& q, Vector& q_next) const;  // an integrated zero rate may round

  // After a step of length h ending at t (s), with the step's contacts (sorted by key) and velocities v:
  // the quiet times, then the islands that fall asleep (their velocities zeroed in v). Returns whether
  // any did. Then `contacts` loses the contacts of the islands asleep and gets every asleep island's
  // kept contacts, in key order (what the probes and the next warm start read).
  bool settle(double h, double t, std::vector<ActiveContact>& contacts, Vector& v);

 private:
  struct Island {
    std::vector<int> bodies;
    std::vector<ActiveContact> contacts;  // sorted by key
  };
  void wake(int island);
  void gather_kept();

  const World& world_;
  SleepParameters parameters_;
  std::vector<char> may_sleep_;     // per body
  std::vector<char> asleep_;        // per body
  std::vector<double> quiet_time_;  // per body, s
  std::vector<int> island_of_;      // per body: its asleep island's index in islands_, −1 when awake
  std::vector<Island> islands_;     // the asleep islands (an emptied entry is free)
  int asleep_count_ = 0;
  long slept_ = 0, woken_ = 0;
  std::vector<ActiveContact> kept_;  // every asleep island's contacts, in key order
  bool kept_changed_ = false;        // an island woke since kept_ was gathered
  std::vector<int> parent_;          // settle's union–find over bodies, and the islands kept awake
  std::vector<char> blocked_;
  std::vector<int> new_island_;      // settle's: by root, the index in islands_ of an island falling asleep
  std::vector<ActiveContact> merged_;
};

}  // namespace csim
