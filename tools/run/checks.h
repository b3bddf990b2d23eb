// Streaming evaluation of a scene's checks: every step's probe values go through an ExtremumTracker
// (turning points, refined by the parabola through the three samples around them where the signal is
// smooth there) and the values at requested times (quadratic interpolation through the three samples
// around the time), so checks use the full time resolution whatever the output rate.
// An extremum is a value the run produced unless the signal is smooth around it: a turning point next
// to a step that closed a contact (an impact: a velocity jumps inside the step, a position turns at a
// kink) or at an event sample is the sample itself, never a parabola through the jump, which
// overshoots by a fraction of the jump (a bouncing ball's −5.26 m/s for an impact at −4.43 m/s). A value
// at a time interpolates the samples since the last jump only (the sample past the time when the jump
// lies in its own interval).
// A mean over a window [t1, t2] is weighted by the Hann window w = sin²(π (t − t1)/(t2 − t1)) (times
// each sample's interval), so that a periodic ripple (a wheel's elements passing the contact) that
// does not fit a whole number of times in the window leaves an error of order (period/window)³
// instead of period/window.
#pragma once

#include "contact/contact_point.h"

#include <optional>
#include <string>
#include <vector>

namespace csim {

struct ActiveContact;    // engine/state.h
struct ExpressionScope;  // expression.h
struct RunSettings;      // scene.h

struct Extremum {
  double time = 0.0;   // s
  double value = 0.0;
  bool maximum = false;
};

// Turning points of a sampled signal. A plateau (a stick phase) between a rise and a fall is one
// extremum; a plateau that lasts to the end after a motion is a final extremum (the body came to rest).
// A turning point is refined by the parabola through it and its two neighbours only when none of them is
// exact and no jump lies between them; otherwise it is the sample, a value the signal took.
class ExtremumTracker {
 public:
  // exact: the sample sits exactly on a turning point (an event), so no parabola is fitted through it.
  // after_jump: the signal may have jumped since the last sample (a step that closed a contact).
  void add(double t, double value, bool exact = false, bool after_jump = false);
  void finish();
  const std::vector<Extremum>& extrema() const { return extrema_; }

 private:
  struct Sample { double t, value; bool exact, after_jump; };
  void record(bool maximum);

  std::vector<Extremum> extrema_;
  std::optional<Sample> last_, pivot_, before_pivot_, after_pivot_;
  int direction_ = 0;   // sign of the last significant change
  bool flat_since_pivot_ = false;
  double scale_ = 0.0;  // largest |value| seen, for the flatness threshold
};

// A check ends in one of four states. Only an evaluated check passes or fails; the two others are
// never a pass, and carry their reason in `note`:
// - excluded (skipped): its only_if is false for these parameters, or could not be evaluated (a
//   reference function that has no answer for them, e.g. a rest time when the mass never stops);
// - not evaluated: it applies, but the run cannot judge it (a time or window beyond the run's end or
//   empty for these parameters, an extremum the run did not reach, a reference that fails, a probe
//   without a value for these parameters). Its value and error are NaN.
struct CheckResult {
  std::string name, probe, kind, source;
  double reference = 0.0, value = 0.0, error = 0.0, time = 0.0;
  double absolute_tolerance = 0.0, relative_tolerance = 0.0;
  bool passed = false;
  bool skipped = false;     // excluded by its only_if
  bool evaluated = true;    // false for excluded and not-evaluated checks
  std::string note;         // why it was excluded or could not be evaluated
};

struct CheckCounts {
  int passed = 0, failed = 0, not_evaluated = 0, excluded = 0;
  int total() const { return passed + failed + not_evaluated + excluded; }
  // The run's verdict: a pass needs at least one evaluated check, no failure, and every check either
  // evaluated or excluded by its own only_if. A scene without checks is not judged (never a pass): it
  // is a plain simulation (RunReport::plain_simulation), which `csim run` ends with exit 0.
  bool pass() const { return passed > 0 && failed == 0 && not_evaluated == 0; }
};
CheckCounts count_checks(const std::vector<CheckResult>& checks);

// The checks of a run stopped by a numerical failure at time t (s): not judged, whatever the samples
// before the failure say (a check of a later time, an extremum or a final value reads what the run did not
// reach), those excluded by their only_if left excluded. Formed from the definitions alone: nothing is
// evaluated on a run cut short.
std::vector<CheckResult> unjudged_checks(const RunSettings& run, double t);

class CheckEvaluator {
 public:
  CheckEvaluator(const RunSettings& run, const ExpressionScope& scope);
  // after_jump: a contact closed since the last sample (ContactClosings), so no parabola spans the two.
  void add_sample(double t, const std::vector<double>& probe_values, bool exact = false, bool after_jump = false);
  // Whether a check reads extrema or values at a time: only then does add_sample need after_jump.
  bool reads_jumps() const { return !extremum_probes_.empty() || !window_probes_.empty(); }
  // The probes whose every sample a check reads (an extremum, a value at a time, a mean): the others
  // are read by final checks alone, at the last sample, so that a run may leave their values stale
  // between its output rows (their entries are not read). The first and the last samples must hold
  // every probe's value (a reference may name the initial one). Their indices, ascending.
  const std::vector<int>& sampled_probes() const { return sampled_; }
  std::vector<CheckResult> finish(double end_time);

 private:
  struct Window { double t[3]; double value[3]; bool after_jump[3] = {false, false, false}; int count = 0; };
  const RunSettings& run_;
  const ExpressionScope& scope_;
  std::vector<ExtremumTracker> trackers_;               // one per probe (extremum_probes_ fed)
  std::vector<Window> windows_;                         // last three samples per probe (window_probes_ fed)
  std::vector<std::optional<double>> at_values_;        // per check (Mode::at)
  std::vector<std::pair<double, double>> mean_sums_;    // per check (Mode::mean): Σ w·value, Σ w
  std::vector<std::size_t> at_checks_, mean_checks_;   // the checks of Mode::at and Mode::mean
  // Listed once, ascending, as add_sample visits them at every step: the sampled probes (see
  // sampled_probes()), and of them those whose extrema an extremum check reads and those whose window
  // an `at` check reads (an undefined, NaN, probe is in neither).
  std::vector<int> sampled_, extremum_probes_, window_probes_;
  double last_time_ = 0.0;
  std::vector<double> last_values_;
  std::vector<double> initial_values_;                 // at t = 0: a reference may be `initial`
};

// The steps that close a contact: a contact that carries a normal impulse and carried none at the step
// before (matched by its key). In a nonsmooth run that is where an impact makes the velocities jump
// inside the step; a contact that was already pressed (a resting body struck again) is not seen.
class ContactClosings {
 public:
  // Whether `contacts` (a step's, engine/state.h) close one; remembers them for the next step.
  bool closed(const std::vector<ActiveContact>& contacts);

 private:
  std::vector<ContactKey> pressed_, current_;  // keys with r_n > 0 at the last step, sorted; scratch
};

}  // namespace csim
