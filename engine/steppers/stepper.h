// A time-stepper advances a State of a World by one step.
#pragma once

#include "engine/state.h"
#include "engine/steppers/summary_entries.h"

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
  // The energies that step() leaves to be asked for, into state.energy: the run asks after each step
  // whose probes read an energy, and at its end. Only the quasi-static stepper leaves one, its elastic
  // energy (a pass over every element that its step does not need); the others close a balance of
  // work at every step.
  virtual void measure_energy(State&) const {}
  // The stepper's part of the run summary: its own settings (written after the integrator's name) and
  // its statistics at the end of a run from `state` (written after the contact solver's).
  virtual void summarize_settings(SummaryEntries&) const {}
  virtual void summarize_statistics(const State&, SummaryEntries&) const {}
  // Whether State::energy closes a balance of work (the quasi-static stepper stores only the elastic
  // energy: no work of prescribed motions, no friction dissipation).
  virtual bool tracks_energy_balance() const { return true; }
};

}  // namespace csim
