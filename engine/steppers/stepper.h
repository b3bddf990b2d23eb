// A time-stepper advances a State of a World by one step.
#pragma once

#include "engine/state.h"

#include <stdexcept>
#include <string>

namespace csim {

// A numerical failure during a run (non-finite values, a contact solve far from converged): carries
// the time at which it happened. Library code throws it; tools/ turns it into a message and exit 2.
struct RunError : std::runtime_error {
  RunError(double time, const std::string& what)
      : std::runtime_error(what), time(time) {}
  double time;  // s
};

class Stepper {
 public:
  virtual ~Stepper() = default;
  virtual void initialize(State& state) = 0;  // fills the initial energies, counters
  virtual void step(State& state) = 0;
};

}  // namespace csim
