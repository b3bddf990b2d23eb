// run_stability_sweep: every run is a fresh load_scene with the user's overrides, the baseline, the case and
// the integrator, in that order, so that it sees exactly what `csim run --set ...` would and the
// study's own settings win. Runs are judged on their final state; nothing is written per run.
#include "tools/studies/stability_sweep.h"

#include "tools/studies/compare.h"
#include "tools/run/probes.h"
#include "tools/run/run.h"
#include "engine/steppers/integrator.h"
#include "tools/scene/scene.h"
#include "tools/scene/scene_error.h"
#include "tools/scene/scene_node.h"
#include "engine/steppers/stepper.h"
#include "tools/run/stop_request.h"
#include "tools/studies/case_failure.h"
#include "tools/studies/case_keys.h"
#include "tools/studies/case_record.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>

namespace csim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---- the sweeps file ----

std::vector<std::string> assignments(const SceneNode& list) {
  std::vector<std::string> out;
  for (const SceneNode& item : list.items()) {
    const std::string text = item.as_string();
    const std::size_t equal = text.find('=');
    if (equal == std::string::npos || equal == 0) item.fail("expected KEY=VALUE (got '" + text + "')");
    out.push_back(text);
  }
  return out;
}

std::vector<std::string> integrator_list(const SceneNode& list) {
  const std::vector<std::string>& known = comparable_integrators();
  std::vector<std::string> out;
  for (const SceneNode& item : list.items()) {
    const std::string name = item.as_string();
    if (std::find(known.begin(), known.end(), name) == known.end())
      item.fail("unknown integrator '" + name + "' (known: " + comparable_integrator_names() + ")");
    if (std::find(out.begin(), out.end(), name) != out.end()) item.fail("'" + name + "' is listed twice");
    out.push_back(name);
  }
  if (out.empty()) list.fail("needs at least one integrator");
  return out;
}

StabilitySweep read_sweep(const std::string& name, const SceneNode& node,
                       const std::vector<std::string>& default_integrators, bool has_default) {
  node.allow_only({"key", "values", "integrators"});
  StabilitySweep sweep;
  sweep.name = name;
  sweep.key = node.string("key");
  sweep.line = node.child("key").line();
  if (sweep.key.empty() || sweep.key.find('=') != std::string::npos)
    node.child("key").fail("expected a dotted key such as parameters.mass");
  for (const SceneNode& item : node.child("values").items()) sweep.values.push_back(item.as_string());
  if (sweep.values.empty()) node.child("values").fail("needs at least one value");
  if (const auto list = node.optional_child("integrators")) {
    sweep.integrators = integrator_list(*list);
  } else {
    if (!has_default) node.fail_at("integrators", "no integrators here and no top-level integrators list");
    sweep.integrators = default_integrators;
  }
  return sweep;
}

// ---- one run ----

void measure_checks(const std::vector<CheckResult>& checks, StabilityRow& row) {
  for (const CheckResult& c : checks)
    if (!c.skipped && !c.passed) row.failed_checks.push_back(c.name);
  row.outcome = row.failed_checks.empty() ? StabilityOutcome::passed : StabilityOutcome::check_failed;
  bool found = false;
  for (const CheckResult& c : checks) {
    if (c.skipped) continue;
    const bool failed = !c.passed;
    if (!row.failed_checks.empty() && !failed) continue;  // the worst of what failed, not of what passed
    const bool evaluated = c.note.empty() && std::isfinite(c.value);
    const double error = !evaluated ? kNaN : c.reference != 0.0 ? std::abs(c.error / c.reference) : std::abs(c.error);
    // A check that could not be evaluated is worse than any number.
    const bool worse = !found || (std::isnan(error) && !std::isnan(row.worst_error)) ||
                       (!std::isnan(row.worst_error) && error > row.worst_error);
    if (!worse) continue;
    found = true;
    row.worst_error = error;
    row.worst_error_relative = c.reference != 0.0;
    row.worst_check = c.name;
  }
}

void judge_energy(const State& state, StabilityRow& row) {
  const EnergyBalance& e = state.energy;
  row.contact_dissipation = e.contact_dissipation;
  row.numerical_dissipation = e.numerical_dissipation;
  row.max_abs_residual = e.max_abs_residual;
  row.energy_scale = std::max({std::abs(e.work_of_loads), e.kinetic + e.elastic, e.initial_kinetic + e.initial_elastic,
                               1e-300});
  const Integrator integrator = *integrator_from_name(row.integrator);
  row.energy_judged = is_time_stepping(integrator);
  if (!row.energy_judged) return;
  const double floor = -kCreatedEnergyTolerance * row.energy_scale;
  if (integrator == Integrator::generalized_alpha) {
    // Its numerical dissipation is what closes the balance (generalized_alpha.h): the energy created is
    // what the contacts and the scheme together did not remove, and the balance is closed by construction.
    row.creates_energy = !(e.contact_dissipation + e.numerical_dissipation >= floor);
    return;
  }
  row.creates_energy = !(e.contact_dissipation >= floor) || !(e.numerical_dissipation >= floor);
  row.balance_open = !(e.max_abs_residual <= kBalanceTolerance * row.energy_scale);
}

void check_finite(const Scene& scene, const RunReport& report, StabilityRow& row) {
  const State& state = report.state;
  if (!state.q.allFinite()) row.non_finite.push_back("positions");
  if (!state.v.allFinite()) row.non_finite.push_back("velocities");
  const EnergyBalance& e = state.energy;
  for (double x : {e.kinetic, e.elastic, e.work_of_loads, e.contact_dissipation, e.numerical_dissipation,
                   e.max_abs_residual})
    if (!std::isfinite(x)) {
      row.non_finite.push_back("energy balance");
      break;
    }
  std::vector<double> values;
  ProbeEvaluator(scene.world, scene.run).evaluate(state, values);
  for (std::size_t k = 0; k < values.size() && k < scene.run.probes.size(); ++k)
    if (!std::isfinite(values[k])) row.non_finite.push_back("probe " + scene.run.probes[k].name);
}

void run_case(const std::vector<std::string>& overrides, const std::string& scene_file, StabilityRow& row) {
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  try {
    const auto scene = load_scene(scene_file, overrides);
    const RunReport report = run_scene(*scene, RunOptions{});
    row.wall_time = report.wall_time;
    row.steps = is_time_stepping(*integrator_from_name(row.integrator)) ? report.state.counters.steps : report.state.ida.steps;
    measure_checks(report.checks, row);
    judge_energy(report.state, row);
    check_finite(*scene, report, row);
  } catch (const SceneError& e) {
    row.outcome = StabilityOutcome::bad_input;
    row.wall_time = elapsed();
    row.message = e.what();
  } catch (const std::exception&) {  // case_failure.h
    const CaseFailure failure = current_case_failure();
    row.wall_time = elapsed();
    row.message = failure.message;
    // What the integrator refuses other than in the scene's terms is a stop all the same.
    row.outcome = failure.kind == CaseFailureKind::environment_failure ? StabilityOutcome::environment_failure
                                                                      : StabilityOutcome::stopped;
    row.stopped_at = failure.kind == CaseFailureKind::numerical_failure ? failure.time : kNaN;
  }
}

std::vector<StabilitySweep> selected_sweeps(const StabilityPlan& plan, const std::vector<std::string>& only) {
  if (only.empty()) return plan.sweeps;
  std::vector<StabilitySweep> out;
  for (const std::string& name : only) {
    const auto sweep = std::find_if(plan.sweeps.begin(), plan.sweeps.end(),
                                    [&](const StabilitySweep& s) { return s.name == name; });
    if (sweep == plan.sweeps.end()) {
      std::string known;
      for (const StabilitySweep& s : plan.sweeps) known += (known.empty() ? "" : ", ") + s.name;
      throw SceneError(plan.file, 0, "--only", "no sweep named '" + name + "' (sweeps: " + known + ")");
    }
    out.push_back(*sweep);
  }
  return out;
}

// The whole study's inputs are checked before its first run: a baseline or a sweep key the scene
// rejects would otherwise fail every case alike.
std::unique_ptr<Scene> load_with_baseline(const StabilityOptions& options, const StabilityPlan& plan,
                                          const std::vector<std::string>& common) {
  try {
    return load_scene(options.scene_file, common);
  } catch (const SceneError& e) {
    throw SceneError(plan.file, plan.baseline_line, "baseline", std::string("the scene rejects it: ") + e.what());
  }
}

// Every sweep key with every integrator of its sweep (case_keys.h).
void check_sweep_keys(const StabilityPlan& plan, const std::vector<StabilitySweep>& sweeps, const Scene& scene) {
  for (const StabilitySweep& sweep : sweeps)
    for (const std::string& name : sweep.integrators)
      if (const auto problem = case_key_problem(scene, sweep.key, *integrator_from_name(name)))
        throw SceneError(plan.file, sweep.line, "sweeps." + sweep.name + ".key", *problem);
}

// A run's row as the study runner carries it (case_record.h).
std::string row_record(const StabilityRow& row) {
  RecordWriter out;
  out.text(row.sweep).text(row.key).text(row.value).text(row.integrator).integer(static_cast<int>(row.outcome));
  out.number(row.worst_error).flag(row.worst_error_relative).text(row.worst_check).texts(row.failed_checks);
  out.flag(row.energy_judged).number(row.contact_dissipation).number(row.numerical_dissipation);
  out.number(row.max_abs_residual).number(row.energy_scale).flag(row.creates_energy).flag(row.balance_open);
  out.texts(row.non_finite).number(row.wall_time).integer(row.steps).number(row.stopped_at).text(row.message);
  return out.bytes();
}

StabilityRow read_row(const std::string& record) {
  RecordReader in(record);
  StabilityRow row;
  row.sweep = in.text();
  row.key = in.text();
  row.value = in.text();
  row.integrator = in.text();
  row.outcome = static_cast<StabilityOutcome>(in.integer());
  row.worst_error = in.number();
  row.worst_error_relative = in.flag();
  row.worst_check = in.text();
  row.failed_checks = in.texts();
  row.energy_judged = in.flag();
  row.contact_dissipation = in.number();
  row.numerical_dissipation = in.number();
  row.max_abs_residual = in.number();
  row.energy_scale = in.number();
  row.creates_energy = in.flag();
  row.balance_open = in.flag();
  row.non_finite = in.texts();
  row.wall_time = in.number();
  row.steps = in.integer();
  row.stopped_at = in.number();
  row.message = in.text();
  return row;
}

}  // namespace

const char* outcome_name(StabilityOutcome outcome) {
  switch (outcome) {
    case StabilityOutcome::passed: return "passed";
    case StabilityOutcome::check_failed: return "check failed";
    case StabilityOutcome::stopped: return "stopped";
    case StabilityOutcome::bad_input: return "bad input";
    case StabilityOutcome::environment_failure: return "environment failure";
  }
  return "?";
}

// A Moreau–Jean or generalized-α run must reach the end: its stops are non-finite values or a contact
// solve far from converged, and its energy invariants cannot be verified on a run that did not finish.
bool StabilityRow::violates_invariant() const {
  if (outcome == StabilityOutcome::bad_input || outcome == StabilityOutcome::environment_failure ||
      !non_finite.empty())
    return true;
  if (!is_time_stepping(*integrator_from_name(integrator))) return false;
  if (outcome == StabilityOutcome::stopped) return true;
  return creates_energy || balance_open;
}

StabilityPlan read_stability_plan(const std::string& file) {
  StabilityPlan plan;
  plan.file = file;
  SceneDocument document = load_scene_document(file);
  const SceneNode root(document.root, "", &document);
  root.allow_only({"baseline", "integrators", "sweeps"});
  if (const auto baseline = root.optional_child("baseline")) {
    plan.baseline = assignments(*baseline);
    plan.baseline_line = baseline->line();
  }
  std::vector<std::string> integrators;
  const auto default_list = root.optional_child("integrators");
  if (default_list) integrators = integrator_list(*default_list);
  const SceneNode sweeps = root.child("sweeps");
  for (const auto& [name, node] : sweeps.entries())
    plan.sweeps.push_back(read_sweep(name, node, integrators, default_list.has_value()));
  if (plan.sweeps.empty()) sweeps.fail("needs at least one sweep");
  return plan;
}

StabilityStudy run_stability_sweep(const StabilityOptions& options, const std::function<void(const StabilityRow&)>& on_row,
                                   StudyRunner& runner) {
  const auto start = std::chrono::steady_clock::now();
  StabilityStudy study;
  study.scene_file = options.scene_file;
  study.sweeps_file = options.sweeps_file.empty()
                          ? (std::filesystem::path(options.scene_file).parent_path() / "stress.yaml").string()
                          : options.sweeps_file;
  load_scene(options.scene_file, options.overrides);  // the user's own mistakes first, named as such
  const StabilityPlan plan = read_stability_plan(study.sweeps_file);
  const std::vector<StabilitySweep> sweeps = selected_sweeps(plan, options.only);
  study.overrides = options.overrides;
  study.placement = runner.placement().text();
  study.baseline = plan.baseline;
  std::vector<std::string> common = options.overrides;
  common.insert(common.end(), plan.baseline.begin(), plan.baseline.end());
  const auto scene = load_with_baseline(options, plan, common);
  check_sweep_keys(plan, sweeps, *scene);
  study.scene_name = scene->name;
  study.description = scene->description;
  std::vector<StabilityRow> cases;
  std::vector<std::vector<std::string>> case_overrides;
  for (const StabilitySweep& sweep : sweeps)
    for (const std::string& value : sweep.values)
      for (const std::string& integrator : sweep.integrators) {
        StabilityRow row;
        row.sweep = sweep.name;
        row.key = sweep.key;
        row.value = value;
        row.integrator = integrator;
        std::vector<std::string> overrides = common;
        overrides.push_back(sweep.key + "=" + value);
        overrides.push_back("integrator.type=" + integrator);
        cases.push_back(std::move(row));
        case_overrides.push_back(std::move(overrides));
      }
  auto run_one = [&](std::size_t index) {
    StabilityRow row = cases[index];
    run_case(case_overrides[index], options.scene_file, row);
    return row_record(row);
  };
  auto take = [&](std::size_t, const std::string& record) {
    StabilityRow row = read_row(record);
    if (on_row) on_row(row);
    study.rows.push_back(std::move(row));
  };
  runner.run(cases.size(), run_one, take);
  study.total_wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return study;
}

}  // namespace csim
