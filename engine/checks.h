// Streaming evaluation of a scene's checks: every step's probe values go through an ExtremumTracker
// (turning points, refined by the parabola through the three samples around them) and the values at
// requested times (quadratic interpolation through the three samples around the time), so checks use
// the full time resolution whatever the output rate.
// A mean over a window [t1, t2] is weighted by the Hann window w = sin²(π (t − t1)/(t2 − t1)) (times
// each sample's interval), so that a periodic ripple (a wheel's elements passing the contact) that
// does not fit a whole number of times in the window leaves an error of order (period/window)³
// instead of period/window.
#pragma once

#include "engine/scene/scene.h"

#include <optional>
#include <string>
#include <vector>

namespace csim {

struct Extremum {
  double time = 0.0;   // s
  double value = 0.0;
  bool maximum = false;
};

// Turning points of a sampled signal. A plateau (a stick phase) between a rise and a fall is one
// extremum; a plateau that lasts to the end after a motion is a final extremum (the body came to rest).
class ExtremumTracker {
 public:
  // exact: the sample sits exactly on a turning point (an event), so no parabola is fitted through it.
  void add(double t, double value, bool exact = false);
  void finish();
  const std::vector<Extremum>& extrema() const { return extrema_; }

 private:
  struct Sample { double t, value; bool exact; };
  void record(bool maximum);

  std::vector<Extremum> extrema_;
  std::optional<Sample> last_, pivot_, before_pivot_, after_pivot_;
  int direction_ = 0;   // sign of the last significant change
  bool flat_since_pivot_ = false;
  double scale_ = 0.0;  // largest |value| seen, for the flatness threshold
};

struct CheckResult {
  std::string name, probe, kind, source;
  double reference = 0.0, value = 0.0, error = 0.0, time = 0.0;
  double absolute_tolerance = 0.0, relative_tolerance = 0.0;
  bool passed = false;
  bool skipped = false;     // only_if false for these parameters
  // False when the run could not evaluate it (a time or window beyond the run's end, an extremum the
  // run did not reach, a reference that fails): never a pass.
  bool evaluated = true;
  std::string note;         // why it could not be evaluated, or why it was skipped
};

class CheckEvaluator {
 public:
  CheckEvaluator(const RunSettings& run, const ExpressionScope& scope);
  void add_sample(double t, const std::vector<double>& probe_values, bool exact = false);
  std::vector<CheckResult> finish(double end_time);

 private:
  struct Window { double t[3]; double value[3]; int count = 0; };
  const RunSettings& run_;
  const ExpressionScope& scope_;
  std::vector<ExtremumTracker> trackers_;               // one per probe
  std::vector<Window> windows_;                         // last three samples per probe
  std::vector<std::optional<double>> at_values_;        // per check (Mode::at)
  std::vector<std::pair<double, double>> mean_sums_;    // per check (Mode::mean): Σ w·value, Σ w
  double last_time_ = 0.0;
  std::vector<double> last_values_;
  std::vector<double> initial_values_;                 // at t = 0: a reference may be `initial`
};

}  // namespace csim
