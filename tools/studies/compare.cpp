// run_comparison: each configuration is a fresh load_scene with the study's overrides, so that every
// run sees exactly what `csim run --set ...` would; the scene loaded with the user's overrides alone
// fixes the checks measured (only_if depends on the parameters, which the study does not change).
#include "tools/studies/compare.h"

#include "tools/run/run.h"
#include "tools/scene/scene.h"
#include "tools/scene/scene_error.h"
#include "engine/steppers/stepper.h"
#include "tools/run/stop_request.h"
#include "tools/studies/case_failure.h"
#include "tools/studies/case_record.h"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cmath>
#include <iomanip>
#include <limits>
#include <new>
#include <sstream>

namespace csim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// moreau-jean and generalized-alpha are refined by their time step; the IDA integrators by their
// tolerances, their time.step being only the sampling interval of the probes.
bool refined_by_step(const std::string& integrator) {
  const std::optional<Integrator> known = integrator_from_name(integrator);
  return known && is_time_stepping(*known);
}


// The shortest text that reads back as the same double, so that an override sets exactly the value asked.
std::string exact_text(double x) {
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, x).ptr;
  return std::string(buffer, end);
}

void validate(const CompareOptions& options) {
  auto fail = [&](const std::string& option, const std::string& message) {
    throw SceneError(options.scene_file, 0, option, message);
  };
  const std::vector<std::string>& known = comparable_integrators();
  if (options.integrators.empty()) fail("--integrators", "no integrator given");
  for (const std::string& name : options.integrators) {
    if (std::find(known.begin(), known.end(), name) == known.end())
      fail("--integrators", "unknown integrator '" + name + "' (known: " + comparable_integrator_names() + ")");
    if (std::count(options.integrators.begin(), options.integrators.end(), name) > 1)
      fail("--integrators", "'" + name + "' is listed twice");
  }
  auto check_list = [&](const std::vector<double>& list, const std::string& option, bool needed,
                        const std::string& what) {
    if (needed && list.empty()) fail(option, "needs a list of " + what + " for the integrators asked");
    for (double x : list)
      if (!(x > 0.0) || !std::isfinite(x))
        fail(option, "every value must be a positive number (got " + exact_text(x) + ")");
  };
  const bool steps_needed = std::any_of(options.integrators.begin(), options.integrators.end(), refined_by_step);
  const bool tolerances_needed = std::any_of(options.integrators.begin(), options.integrators.end(),
                                             [](const std::string& n) { return !refined_by_step(n); });
  check_list(options.steps, "--steps", steps_needed, "time steps");
  check_list(options.tolerances, "--tolerances", tolerances_needed, "tolerances");
  if (options.repeats < 1) fail("--repeats", "must be at least 1");
  const std::string& r = options.reference;
  if (r != "auto" && r != "analytical" && r != "ida-events" && r != "moreau-jean")
    fail("--reference", "expected auto, analytical, ida-events or moreau-jean (got '" + r + "')");
}

std::vector<ComparedCheck> compared_checks(const Scene& scene) {
  std::vector<ComparedCheck> checks;
  for (const CheckDefinition& c : scene.run.checks)
    if (c.enabled && (c.kind == "analytical" || c.kind == "literature"))
      checks.push_back({c.name, c.kind, c.source, c.reference});
  return checks;
}

std::vector<std::string> run_overrides(const CompareOptions& options, const CompareRow& row) {
  std::vector<std::string> overrides = options.overrides;  // the user's first: the study's own win
  overrides.push_back("integrator.type=" + row.integrator);
  if (refined_by_step(row.integrator)) {
    overrides.push_back("time.step=" + exact_text(row.value));
  } else {
    overrides.push_back("integrator.rtol=" + exact_text(row.value));
    overrides.push_back("integrator.atol=" + exact_text(row.value));
  }
  return overrides;
}

double median(std::vector<double> values) {
  if (values.empty()) return kNaN;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// Fills the row's errors from a finished run. A check the run could not evaluate (fewer extrema than
// asked, say: a regularized friction law creeps and never shows the final stop) leaves its cells NaN
// and is named in the row's status; max_rel_error is the largest over the checks that were evaluated,
// so that such a run still has a point on the diagram, its missing features stated beside it.
void measure_errors(const std::vector<CheckResult>& results, std::vector<ComparedCheck>& checks, CompareRow& row) {
  row.errors.assign(checks.size(), kNaN);
  row.relative_errors.assign(checks.size(), kNaN);
  double max_relative = kNaN;
  for (std::size_t k = 0; k < checks.size(); ++k) {
    ComparedCheck& check = checks[k];
    const auto r = std::find_if(results.begin(), results.end(),
                                [&](const CheckResult& c) { return c.name == check.name; });
    const bool evaluated = r != results.end() && !r->skipped && r->note.empty() && std::isfinite(r->value);
    if (!evaluated) {
      row.not_evaluated.push_back(check.name);
      continue;
    }
    row.errors[k] = std::abs(r->value - r->reference);
    if (r->reference != 0.0) row.relative_errors[k] = row.errors[k] / std::abs(r->reference);
    if (!check.reference_known) {
      check.reference_value = r->reference;
      check.reference_known = true;
    }
    if (check.kind == "analytical" && std::isfinite(row.relative_errors[k]))
      max_relative = std::isnan(max_relative) ? row.relative_errors[k] : std::max(max_relative, row.relative_errors[k]);
  }
  row.max_rel_error = max_relative;
}

// Every repeat runs the same deterministic computation; only the wall time differs, so the errors and
// counters are those of the last repeat and a failure stops the repeats at once.
RunReport run_configuration(const CompareOptions& options, std::vector<ComparedCheck>& checks, CompareRow& row) {
  const std::vector<std::string> overrides = run_overrides(options, row);
  RunReport report;
  try {
    for (int repeat = 0; repeat < options.repeats; ++repeat) {
      honour_stop_request();
      const auto scene = load_scene(options.scene_file, overrides);
      report = run_scene(*scene, RunOptions{});
      row.wall_times.push_back(report.wall_time);
    }
    row.ok = true;
    // moreau-jean, generalized-alpha: time steps and PGS sweeps over the run; ida, ida-events: IDA's internal steps and
    // residual evaluations (its work unit: each Newton iteration costs one).
    const bool ida = !refined_by_step(row.integrator);
    row.steps = ida ? report.state.ida.steps : report.state.counters.steps;
    row.solver_iterations = ida ? report.state.ida.residual_evaluations : report.state.counters.total_iterations;
    measure_errors(report.checks, checks, row);
  } catch (const RunError& e) {
    std::ostringstream message;
    message << "numerical failure at t = " << e.time << " s: " << e.what();
    row.failure = message.str();
  } catch (const std::runtime_error& e) {  // SceneError included: an integrator not built yet, a bad step
    row.failure = e.what();
  } catch (const std::bad_alloc&) {  // an environment failure of this run (case_failure.h): the study goes on
    row.failure = current_case_failure().message;
  }
  row.wall_time_median = median(row.wall_times);
  if (!row.ok) {
    row.max_rel_error = kNaN;
    row.errors.assign(checks.size(), kNaN);
    row.relative_errors.assign(checks.size(), kNaN);
  }
  return report;
}

}  // namespace

const std::vector<std::string>& comparable_integrators() {
  static const std::vector<std::string> names{integrator_name(Integrator::moreau_jean),
                                              integrator_name(Integrator::generalized_alpha),
                                              integrator_name(Integrator::ida), integrator_name(Integrator::ida_events)};
  return names;
}

std::string comparable_integrator_names() {
  std::string names;
  for (const std::string& name : comparable_integrators()) names += (names.empty() ? "" : ", ") + name;
  return names;
}

namespace {

struct Trajectory {
  std::vector<double> times;
  std::vector<std::vector<double>> values;
  std::vector<bool> compared;  // per probe: displacements and positions (forces jump at every switch,
                               // and an energy residual has no scale of its own)
};

// Linear interpolation of probe p of the reference at t (clamped to its window).
double reference_at(const Trajectory& reference, std::size_t p, double t) {
  const auto& times = reference.times;
  if (t <= times.front()) return reference.values.front()[p];
  if (t >= times.back()) return reference.values.back()[p];
  const std::size_t i = std::upper_bound(times.begin(), times.end(), t) - times.begin();
  const double w = (t - times[i - 1]) / (times[i] - times[i - 1]);
  return (1.0 - w) * reference.values[i - 1][p] + w * reference.values[i][p];
}

// Largest, over the probes, of max_t |p(t) − p_ref(t)| / max_t |p_ref(t)|.
double trajectory_error(const RunReport& run, const Trajectory& reference) {
  double worst = 0.0;
  const std::size_t probes = reference.values.empty() ? 0 : reference.values.front().size();
  for (std::size_t p = 0; p < probes; ++p) {
    if (!reference.compared[p]) continue;
    double scale = 0.0, deviation = 0.0;
    for (const auto& row : reference.values) scale = std::max(scale, std::abs(row[p]));
    for (std::size_t k = 0; k < run.sample_times.size(); ++k)
      deviation = std::max(deviation, std::abs(run.samples[k][p] - reference_at(reference, p, run.sample_times[k])));
    if (scale > 0.0) worst = std::max(worst, deviation / scale);
  }
  return worst;
}

bool has_analytical_checks(const Scene& scene) {
  for (const CheckDefinition& c : scene.run.checks)
    if (c.enabled && c.kind == "analytical") return true;
  return false;
}

// Runs the reference; returns false (and leaves `why`) when it cannot run.
bool reference_run(const CompareOptions& options, const std::string& kind, Trajectory& trajectory,
                   std::string& description, std::string& why) {
  std::vector<std::string> overrides = options.overrides;
  if (kind == "ida-events") {
    overrides.insert(overrides.end(), {"integrator.type=ida-events", "integrator.rtol=1e-10", "integrator.atol=1e-12"});
    description = "a converged ida-events run (rtol 1e-10, atol 1e-12)";
  } else {
    const double finest = options.steps.empty() ? load_scene(options.scene_file, options.overrides)->run.step
                                                : *std::min_element(options.steps.begin(), options.steps.end());
    std::ostringstream step;
    step << "time.step=" << std::setprecision(17) << finest / 100.0;
    overrides.insert(overrides.end(), {"integrator.type=moreau-jean", step.str()});
    description = "a Moreau-Jean run at " + step.str() + " (100 times finer than the finest step asked)";
  }
  try {
    honour_stop_request();
    const RunReport report = run_scene(*load_scene(options.scene_file, overrides), RunOptions{});
    trajectory.times = report.sample_times;
    trajectory.values = report.samples;
    const auto scene = load_scene(options.scene_file, options.overrides);
    for (const ProbeDefinition& probe : scene->run.probes)
      trajectory.compared.push_back(probe.kind == ProbeDefinition::Kind::displacement ||
                                    probe.kind == ProbeDefinition::Kind::position);
    return true;
  } catch (const std::exception& e) {
    why = e.what();
    return false;
  }
}

// A configuration's row and the reference values its run evaluated, as the study runner carries them.
std::string configuration_record(const CompareRow& row, const std::vector<ComparedCheck>& checks) {
  RecordWriter out;
  out.text(row.integrator).text(row.parameter).number(row.value).numbers(row.wall_times).number(row.wall_time_median);
  out.integer(row.steps).integer(row.solver_iterations).flag(row.ok).text(row.failure).number(row.max_rel_error);
  out.numbers(row.errors).numbers(row.relative_errors).texts(row.not_evaluated);
  out.integer(static_cast<std::int64_t>(checks.size()));
  for (const ComparedCheck& check : checks) out.flag(check.reference_known).number(check.reference_value);
  return out.bytes();
}

CompareRow read_configuration(const std::string& record, std::vector<ComparedCheck>& checks) {
  RecordReader in(record);
  CompareRow row;
  row.integrator = in.text();
  row.parameter = in.text();
  row.value = in.number();
  row.wall_times = in.numbers();
  row.wall_time_median = in.number();
  row.steps = in.integer();
  row.solver_iterations = in.integer();
  row.ok = in.flag();
  row.failure = in.text();
  row.max_rel_error = in.number();
  row.errors = in.numbers();
  row.relative_errors = in.numbers();
  row.not_evaluated = in.texts();
  const std::int64_t count = in.integer();
  for (std::int64_t k = 0; k < count; ++k) {
    const bool known = in.flag();
    const double value = in.number();
    ComparedCheck& check = checks.at(static_cast<std::size_t>(k));
    if (known && !check.reference_known) {
      check.reference_value = value;
      check.reference_known = true;
    }
  }
  return row;
}

}  // namespace

Comparison run_comparison(const CompareOptions& options, const std::function<void(const CompareRow&)>& on_row,
                          StudyRunner& runner) {
  validate(options);
  // A bad --set is bad input for the whole study, not a failure of each run.
  const auto scene = load_scene(options.scene_file, options.overrides);
  Comparison comparison;
  comparison.scene_name = scene->name;
  comparison.scene_file = options.scene_file;
  comparison.description = scene->description;
  comparison.overrides = options.overrides;
  comparison.placement = runner.placement().text();
  comparison.checks = compared_checks(*scene);

  Trajectory reference;
  std::string kind = options.reference;
  if (kind == "auto") kind = has_analytical_checks(*scene) ? "analytical" : "ida-events";
  if (kind == "analytical") {
    comparison.reference = "the scene's analytical checks";
  } else {
    std::string why;
    if (!reference_run(options, kind, reference, comparison.reference, why)) {
      if (options.reference != "auto" || kind != "ida-events")
        throw std::runtime_error("the reference run (" + kind + ") failed: " + why);
      kind = "moreau-jean";  // the event-driven reference does not apply to this scene: refine instead
      if (!reference_run(options, kind, reference, comparison.reference, why))
        throw std::runtime_error("the reference run (moreau-jean) failed: " + why);
    }
    comparison.trajectory_reference = true;
  }

  std::vector<CompareRow> configurations;
  for (const std::string& integrator : options.integrators) {
    const bool by_step = refined_by_step(integrator);
    for (double value : by_step ? options.steps : options.tolerances) {
      CompareRow row;
      row.integrator = integrator;
      row.parameter = by_step ? "time.step" : "integrator.rtol";
      row.value = value;
      configurations.push_back(row);
    }
  }
  auto run_one = [&](std::size_t index) {
    CompareRow row = configurations[index];
    std::vector<ComparedCheck> checks = comparison.checks;  // this run's own: which references it evaluated
    const RunReport report = run_configuration(options, checks, row);
    if (comparison.trajectory_reference && row.ok) row.max_rel_error = trajectory_error(report, reference);
    return configuration_record(row, checks);
  };
  // A check's reference value is the one of the first run, in study order, that evaluated it.
  auto take = [&](std::size_t, const std::string& record) {
    CompareRow row = read_configuration(record, comparison.checks);
    if (on_row) on_row(row);
    comparison.rows.push_back(std::move(row));
  };
  runner.run(configurations.size(), run_one, take);
  return comparison;
}

}  // namespace csim
