#include "tools/run/checks.h"

#include "tools/scene/scene.h"
#include "engine/state.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace csim {

namespace {

// Relative change per sample below which a signal is at rest. It must stay far below the smallest
// real change near a turning point (½ a h², 2.5e-10 m at h = 1e-5 s on SDNV104): a looser value
// (1e-10 was tried) shaves a flat zone off every extremum and costs the times their accuracy. So a
// regularized law, which creeps instead of sticking, shows no final stop: that is its error.
constexpr double kFlatness = 1e-13;

// Vertex of the parabola through three samples (any spacing); falls back to the middle sample.
Extremum parabola_vertex(double t0, double y0, double t1, double y1, double t2, double y2, bool maximum) {
  const double d1 = (y1 - y0) / (t1 - t0), d2 = (y2 - y1) / (t2 - t1);
  const double a = (d2 - d1) / (t2 - t0);  // half the second derivative
  Extremum e{t1, y1, maximum};
  if (a == 0.0) return e;
  const double b = d1 - a * (t0 + t1);     // y = a t² + b t + c
  const double t = -b / (2.0 * a);
  if (t < t0 || t > t2) return e;
  e.time = t;
  e.value = y1 + a * (t - t1) * (t - t1) + (2.0 * a * t1 + b) * (t - t1);
  return e;
}

// The interpolant through the last `count` (1 to 3) of the three samples t, y.
double quadratic_at(const double t[3], const double y[3], int count, double at) {
  if (count == 1) return y[2];
  if (count == 2) return y[1] + (y[2] - y[1]) * (at - t[1]) / (t[2] - t[1]);
  double value = 0.0;
  for (int i = 0; i < 3; ++i) {
    double basis = 1.0;
    for (int j = 0; j < 3; ++j)
      if (j != i) basis *= (at - t[j]) / (t[i] - t[j]);
    value += basis * y[i];
  }
  return value;
}

}  // namespace

void ExtremumTracker::add(double t, double value, bool exact, bool after_jump) {
  scale_ = std::max(scale_, std::abs(value));
  const Sample s{t, value, exact, after_jump};
  if (!last_) {
    last_ = pivot_ = s;
    return;
  }
  const double change = value - last_->value;
  // Flat: a stick phase or rest.
  if (std::abs(change) <= kFlatness * scale_) {
    if (last_->t == pivot_->t) flat_since_pivot_ = true;
    last_ = s;
    return;
  }
  const int direction = change > 0.0 ? 1 : -1;
  if (direction_ != 0 && direction != direction_) {
    after_pivot_.reset();
    if (!flat_since_pivot_ && last_->t == pivot_->t) after_pivot_ = s;
    record(direction_ > 0);
  }
  before_pivot_ = last_;
  pivot_ = s;
  flat_since_pivot_ = false;
  direction_ = direction;
  last_ = s;
}

void ExtremumTracker::record(bool maximum) {
  // The parabola spans (before, pivot] and (pivot, after]: a jump in either is no turning point of a
  // smooth signal, and the vertex would overshoot the values on both sides of it.
  if (before_pivot_ && after_pivot_ && !pivot_->exact && !pivot_->after_jump && !after_pivot_->after_jump)
    extrema_.push_back(parabola_vertex(before_pivot_->t, before_pivot_->value, pivot_->t, pivot_->value,
                                       after_pivot_->t, after_pivot_->value, maximum));
  else
    extrema_.push_back(Extremum{pivot_->t, pivot_->value, maximum});
}

void ExtremumTracker::finish() {
  if (direction_ != 0 && flat_since_pivot_) {
    after_pivot_.reset();
    record(direction_ > 0);
    direction_ = 0;
  }
}

CheckEvaluator::CheckEvaluator(const RunSettings& run, const ExpressionScope& scope)
    : run_(run), scope_(scope), trackers_(run.probes.size()), windows_(run.probes.size()),
      at_values_(run.checks.size()), mean_sums_(run.checks.size(), {0.0, 0.0}) {
  // Listed once: add_sample runs at every step.
  using Mode = CheckDefinition::Mode;
  std::vector<bool> sampled(run.probes.size(), false), extremum(run.probes.size(), false),
      windowed(run.probes.size(), false);
  for (std::size_t c = 0; c < run.checks.size(); ++c) {
    const Mode mode = run.checks[c].mode;
    const int probe = run.checks[c].probe;
    if (mode == Mode::at) at_checks_.push_back(c);
    if (mode == Mode::mean) mean_checks_.push_back(c);
    if (mode == Mode::final_value || probe < 0) continue;
    sampled[probe] = true;
    if (mode == Mode::at) windowed[probe] = true;
    else if (mode != Mode::mean) extremum[probe] = true;
  }
  for (std::size_t p = 0; p < run.probes.size(); ++p) {
    if (!sampled[p]) continue;
    sampled_.push_back(static_cast<int>(p));
    if (!run.probes[p].undefined.empty()) continue;
    if (extremum[p]) extremum_probes_.push_back(static_cast<int>(p));
    if (windowed[p]) window_probes_.push_back(static_cast<int>(p));
  }
}

void CheckEvaluator::add_sample(double t, const std::vector<double>& values, bool exact, bool after_jump) {
  // A probe that is undefined (NaN) is not tracked: its checks are not evaluated. One that only final
  // checks read is not either: last_values_ serves them. A probe's extrema are found only if a check
  // reads them, and its last three samples kept only if a check reads its value at a time.
  for (const int p : extremum_probes_) trackers_[p].add(t, values[p], exact, after_jump);
  for (const int p : window_probes_) {
    Window& w = windows_[p];
    for (int i = 0; i < 2; ++i) {
      w.t[i] = w.t[i + 1];
      w.value[i] = w.value[i + 1];
      w.after_jump[i] = w.after_jump[i + 1];
    }
    w.t[2] = t;
    w.value[2] = values[p];
    w.after_jump[2] = after_jump;
    w.count = std::min(w.count + 1, 3);
  }
  for (const std::size_t c : at_checks_) {
    const CheckDefinition& check = run_.checks[c];
    if (at_values_[c]) continue;
    // The sample at or just past the requested time (within rounding of the step count).
    if (t < check.time - 1e-9 * run_.step) continue;
    // The samples since the last jump: no interpolant spans one (checks.h).
    const Window& w = windows_[check.probe];
    const int count = w.after_jump[2] ? 1 : w.after_jump[1] ? std::min(w.count, 2) : w.count;
    at_values_[c] = quadratic_at(w.t, w.value, count, check.time);
  }
  for (const std::size_t c : mean_checks_) {
    const CheckDefinition& check = run_.checks[c];
    if (initial_values_.empty()) continue;
    if (t <= check.time || t >= check.time_end) continue;
    const double s = std::sin(M_PI * (t - check.time) / (check.time_end - check.time));
    const double weight = s * s * (t - last_time_);
    mean_sums_[c].first += weight * values[check.probe];
    mean_sums_[c].second += weight;
  }
  if (initial_values_.empty()) initial_values_ = values;
  last_values_ = values;
  last_time_ = t;
}

// A check's result before it is judged: what its definition names (check, probe, kind, source, tolerances).
static CheckResult check_heading(const RunSettings& run, const CheckDefinition& check) {
  CheckResult r;
  r.name = check.name;
  r.probe = run.probes[check.probe].name;
  r.kind = check.kind;
  r.source = check.source;
  r.absolute_tolerance = check.absolute_tolerance;
  r.relative_tolerance = check.relative_tolerance;
  return r;
}

std::vector<CheckResult> unjudged_checks(const RunSettings& run, double t) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::ostringstream why;
  why << "not evaluated: the run stopped by a numerical failure at t = " << t << " s";
  std::vector<CheckResult> results;
  for (const CheckDefinition& check : run.checks) {
    CheckResult r = check_heading(run, check);
    r.reference = r.value = r.error = r.time = nan;
    r.evaluated = false;
    r.skipped = !check.enabled;
    r.note = check.enabled ? why.str() : "excluded: " + check.exclusion;
    results.push_back(r);
  }
  return results;
}

std::vector<CheckResult> CheckEvaluator::finish(double end_time) {
  for (ExtremumTracker& tracker : trackers_) tracker.finish();
  std::vector<CheckResult> results;
  for (std::size_t c = 0; c < run_.checks.size(); ++c) {
    const CheckDefinition& check = run_.checks[c];
    CheckResult r = check_heading(run_, check);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const auto not_evaluated = [&](const std::string& why) {
      r.evaluated = false;
      r.value = r.error = nan;
      r.note = "not evaluated: " + why;
      results.push_back(r);
    };
    if (!check.enabled) {
      r.skipped = true;
      r.evaluated = false;
      r.value = r.error = r.reference = nan;
      r.note = "excluded: " + check.exclusion;
      results.push_back(r);
      continue;
    }
    if (!check.unjudgeable.empty()) {
      not_evaluated(check.unjudgeable);
      continue;
    }
    if (const std::string& undefined = run_.probes[check.probe].undefined; !undefined.empty()) {
      not_evaluated("probe '" + r.probe + "' has no value for these parameters: " + undefined);
      continue;
    }
    bool found = true;
    using Mode = CheckDefinition::Mode;
    switch (check.mode) {
      case Mode::at:
        found = at_values_[c].has_value();
        r.time = check.time;
        if (found) r.value = *at_values_[c];
        else if (check.time > end_time) r.note = "its time lies beyond the run's end";
        break;
      case Mode::mean:
        r.time = check.time_end;
        found = mean_sums_[c].second > 0.0 && check.time_end <= end_time * (1.0 + 1e-12);
        if (found) r.value = mean_sums_[c].first / mean_sums_[c].second;
        else if (check.time_end > end_time) r.note = "its window reaches beyond the run's end";
        else r.note = "no sample inside the mean's window";
        break;
      case Mode::final_value:
        r.time = end_time;
        found = !last_values_.empty();
        if (found) r.value = last_values_[check.probe];
        break;
      default: {
        std::vector<Extremum> selected;
        for (const Extremum& e : trackers_[check.probe].extrema())
          if (check.mode == Mode::extremum || check.mode == Mode::extremum_time ||
              (check.mode == Mode::maximum) == e.maximum)
            selected.push_back(e);
        found = check.index <= static_cast<int>(selected.size());
        if (found) {
          const Extremum& e = selected[check.index - 1];
          r.time = e.time;
          r.value = check.mode == Mode::extremum_time ? e.time : e.value;
        } else {
          r.note = "the run shows only " + std::to_string(selected.size()) + " such extrema";
        }
      }
    }
    if (!found) {
      not_evaluated(r.note.empty() ? "no sample at the requested time" : r.note);
      continue;
    }
    ExpressionScope scope = scope_;
    scope.variables["t"] = r.time;
    scope.variables["initial"] = initial_values_.empty() ? 0.0 : initial_values_[check.probe];
    try {
      r.reference = evaluate_expression(check.reference, scope);
    } catch (const std::exception& e) {
      r.reference = nan;
      not_evaluated(std::string("the reference could not be evaluated: ") + e.what());
      continue;
    }
    r.error = r.value - r.reference;
    r.passed = std::isfinite(r.value) &&
               std::abs(r.error) <= r.absolute_tolerance + r.relative_tolerance * std::abs(r.reference);
    results.push_back(r);
  }
  return results;
}

bool ContactClosings::closed(const std::vector<ActiveContact>& contacts) {
  current_.clear();
  for (const ActiveContact& c : contacts)
    if (c.impulse(0) > 0.0) current_.push_back(c.point.key);
  std::sort(current_.begin(), current_.end());
  // Every pressed key of this step among the last step's (both sorted)?
  const bool closed = !std::includes(pressed_.begin(), pressed_.end(), current_.begin(), current_.end());
  pressed_.swap(current_);
  return closed;
}

CheckCounts count_checks(const std::vector<CheckResult>& checks) {
  CheckCounts n;
  for (const CheckResult& c : checks) {
    if (c.skipped) ++n.excluded;
    else if (!c.evaluated) ++n.not_evaluated;
    else if (c.passed) ++n.passed;
    else ++n.failed;
  }
  return n;
}

}  // namespace csim
