// Wall-clock time per phase of a step (s), for State::timers. A stepper starts the clock at each step
// and laps it after each phase; a lap adds the time since the last one to that phase, times `scale`.
// A step costing about a microsecond (a lumped Moreau–Jean step) is timed on one step in 16 and
// scaled by 16, since a clock read costs ~20 ns; a Newton step (finite strain, quasi-static) costs
// 0.1 ms or more and is timed whole, every iteration.
#pragma once

#include <chrono>

namespace csim {

class PhaseClock {
 public:
  void start(bool timed, double scale = 1.0) {
    timed_ = timed;
    scale_ = scale;
    if (timed_) mark_ = Clock::now();
  }
  void lap(double& phase) {
    if (!timed_) return;
    const Clock::time_point now = Clock::now();
    phase += scale_ * std::chrono::duration<double>(now - mark_).count();
    mark_ = now;
  }

 private:
  using Clock = std::chrono::steady_clock;
  bool timed_ = false;
  double scale_ = 1.0;
  Clock::time_point mark_;
};

}  // namespace csim
