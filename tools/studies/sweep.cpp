// run_sweep: every case is a fresh load_scene with the user's overrides, the baseline and the case's own
// settings, in that order, so that it sees exactly what `csim run --set ...` would and its own settings win.
#include "tools/studies/sweep.h"

#include "tools/output/atomic_file.h"
#include "tools/run/run.h"
#include "tools/run/stop_request.h"
#include "tools/scene/scene.h"
#include "tools/scene/scene_error.h"
#include "tools/scene/scene_node.h"
#include "tools/studies/case_failure.h"
#include "tools/studies/case_keys.h"
#include "tools/studies/case_record.h"
#include "tools/studies/stability_sweep.h"
#include "engine/steppers/stepper.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

namespace csim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct ValueList {
  std::string key;
  std::vector<std::string> values;
};

// KEY=V1,V2,...: every value non-empty (a value holding a comma needs a sweeps file).
ValueList read_list(const SweepOptions& options, const std::string& option, const std::string& text) {
  auto fail = [&](const std::string& message) { throw SceneError(options.scene_file, 0, option, message); };
  const std::size_t equal = text.find('=');
  if (equal == std::string::npos || equal == 0) fail("expected KEY=V1,V2,... (got '" + text + "')");
  ValueList list;
  list.key = text.substr(0, equal);
  std::string rest = text.substr(equal + 1);
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = rest.find(',', start);
    list.values.push_back(rest.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (list.values.back().empty()) fail("an empty value in '" + text + "'");
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return list;
}

std::vector<SweepCase> cases_from_lists(const SweepOptions& options) {
  std::vector<ValueList> lists, grids;
  for (const std::string& text : options.set_lists) lists.push_back(read_list(options, "--set-list", text));
  for (const std::string& text : options.grids) grids.push_back(read_list(options, "--grid", text));
  std::vector<std::string> keys;
  for (const auto* group : {&lists, &grids})
    for (const ValueList& list : *group) {
      if (std::find(keys.begin(), keys.end(), list.key) != keys.end())
        throw SceneError(options.scene_file, 0, group == &lists ? "--set-list" : "--grid",
                         "'" + list.key + "' is given twice");
      keys.push_back(list.key);
    }
  std::vector<SweepCase> outer(1);
  if (!lists.empty()) {
    const std::size_t length = lists.front().values.size();
    for (const ValueList& list : lists)
      if (list.values.size() != length)
        throw SceneError(options.scene_file, 0, "--set-list",
                         "the lists have different lengths (" + lists.front().key + ": " + std::to_string(length) +
                             ", " + list.key + ": " + std::to_string(list.values.size()) + ")");
    outer.assign(length, {});
    for (std::size_t i = 0; i < length; ++i)
      for (const ValueList& list : lists) {
        outer[i].settings.push_back(list.key + "=" + list.values[i]);
        outer[i].origins.push_back({options.scene_file, 0, "--set-list"});
      }
  }
  std::vector<SweepCase> cases = outer;
  for (const ValueList& grid : grids) {  // each grid key varies faster than the ones before it
    std::vector<SweepCase> next;
    for (const SweepCase& c : cases)
      for (const std::string& value : grid.values) {
        next.push_back(c);
        next.back().settings.push_back(grid.key + "=" + value);
        next.back().origins.push_back({options.scene_file, 0, "--grid"});
      }
    cases = std::move(next);
  }
  return cases;
}

// KEY=VALUE items of a list in a sweeps file; each item's origin in `origins` when given.
std::vector<std::string> settings_of(const SceneNode& list, std::vector<SettingOrigin>* origins = nullptr) {
  std::vector<std::string> out;
  for (const SceneNode& item : list.items()) {
    const std::string text = item.as_string();
    if (text.find('=') == std::string::npos || text.front() == '=') item.fail("expected KEY=VALUE (got '" + text + "')");
    out.push_back(text);
    if (origins) origins->push_back({item.document().file, item.line(), "cases"});
  }
  return out;
}

// A file of explicit cases: `baseline: [KEY=VALUE, ...]` (optional) and `cases: [[KEY=VALUE, ...], ...]`.
std::vector<SweepCase> cases_from_file(const std::string& file, std::vector<std::string>* baseline) {
  SceneDocument document = load_scene_document(file);
  const SceneNode root(document.root, "", &document);
  root.allow_only({"baseline", "cases"});
  if (const auto list = root.optional_child("baseline"))
    if (baseline) *baseline = settings_of(*list);
  std::vector<SweepCase> cases;
  const SceneNode list = root.child("cases");
  for (const SceneNode& item : list.items()) {
    SweepCase c;
    c.settings = settings_of(item, &c.origins);
    cases.push_back(std::move(c));
  }
  if (cases.empty()) list.fail("needs at least one case");
  return cases;
}

// Every key every case sets, under the integrator the case runs, before the first case (case_keys.h).
void check_case_keys(const Scene& scene, const std::vector<SweepCase>& cases) {
  const std::string type = "integrator.type=";
  for (const SweepCase& c : cases) {
    Integrator integrator = scene.run.integrator;
    for (const std::string& setting : c.settings)
      if (setting.rfind(type, 0) == 0)  // an unknown name: the case's own bad value, in its row
        integrator = integrator_from_name(setting.substr(type.size())).value_or(integrator);
    for (std::size_t k = 0; k < c.settings.size(); ++k) {
      const std::string key = c.settings[k].substr(0, c.settings[k].find('='));
      if (const auto problem = case_key_problem(scene, key, integrator)) {
        const SettingOrigin& origin = c.origins[k];
        throw SceneError(origin.file, origin.line, origin.path, *problem);
      }
    }
  }
}

void fill_checks(const std::vector<CheckResult>& results, SweepRow& row) {
  for (const CheckResult& c : results) {
    SweepCheck check;
    check.name = c.name;
    check.value = c.evaluated ? c.value : kNaN;
    if (c.skipped) check.verdict = "excluded";
    else if (!c.evaluated) check.verdict = "not evaluated";
    else check.verdict = c.passed ? "passed" : "failed";
    row.checks.push_back(check);
  }
}

// One case, its outputs in `directory` (none when empty); a file it cannot write is named in `shown`,
// the folder the user asked for, rather than in the temporary folder `written` that holds `directory`.
SweepRow run_one(const std::string& scene_file, const std::vector<std::string>& overrides,
                 const std::string& directory, const std::string& written, const std::string& shown) {
  SweepRow row;
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  try {
    const auto scene = load_scene(scene_file, overrides);
    RunOptions options;
    options.output_directory = directory;
    RunReport report;
    try {
      report = run_scene(*scene, options);
    } catch (const FileWriteError& e) {
      throw e.in_folder(written, shown);
    }
    const State& state = report.state;
    row.exit_status = report.passed() || report.plain_simulation() ? 0 : 1;
    row.status = report.passed() ? "passed" : report.plain_simulation() ? "no checks" : "not a pass";
    row.end_time = state.t;
    row.steps = is_ida(scene->run.integrator) ? state.ida.steps : state.counters.steps;
    row.contact_solves = state.counters.solves;
    row.solver_sweeps = state.counters.total_iterations;
    row.not_converged = state.counters.not_converged;
    row.max_residual = state.counters.max_residual;
    row.newton_iterations = state.counters.newton_iterations;
    row.newton_max = state.counters.max_newton_iterations;
    fill_checks(report.checks, row);
    row.wall_time = report.wall_time;
  } catch (const std::exception&) {  // a value the scene rejects, a numerical failure, a full disk (case_failure.h)
    const CaseFailure failure = current_case_failure();
    row.status = case_failure_status(failure.kind);
    if (failure.kind == CaseFailureKind::numerical_failure) row.end_time = failure.time;
    row.message = failure.message;
    row.wall_time = elapsed();
  }
  return row;
}

std::string row_record(const SweepRow& row) {
  RecordWriter out;
  out.texts(row.settings).integer(row.exit_status).text(row.status).text(row.message).number(row.end_time);
  out.integer(row.steps).integer(row.contact_solves).integer(row.solver_sweeps).integer(row.not_converged);
  out.number(row.max_residual).integer(row.newton_iterations).integer(row.newton_max);
  out.integer(static_cast<std::int64_t>(row.checks.size()));
  for (const SweepCheck& c : row.checks) out.text(c.name).number(c.value).text(c.verdict);
  out.number(row.wall_time);
  return out.bytes();
}

SweepRow read_row(const std::string& record) {
  RecordReader in(record);
  SweepRow row;
  row.settings = in.texts();
  row.exit_status = static_cast<int>(in.integer());
  row.status = in.text();
  row.message = in.text();
  row.end_time = in.number();
  row.steps = in.integer();
  row.contact_solves = in.integer();
  row.solver_sweeps = in.integer();
  row.not_converged = in.integer();
  row.max_residual = in.number();
  row.newton_iterations = in.integer();
  row.newton_max = in.integer();
  row.checks.resize(static_cast<std::size_t>(in.integer()));
  for (SweepCheck& c : row.checks) {
    c.name = in.text();
    c.value = in.number();
    c.verdict = in.text();
  }
  row.wall_time = in.number();
  return row;
}

}  // namespace

std::vector<SweepCase> sweep_cases(const SweepOptions& options, std::vector<std::string>* baseline) {
  const bool lists = !options.set_lists.empty() || !options.grids.empty();
  if (lists && !options.sweeps_file.empty())
    throw SceneError(options.scene_file, 0, "--sweeps", "give either a sweeps file or --set-list/--grid, not both");
  if (!lists && options.sweeps_file.empty())
    throw SceneError(options.scene_file, 0, "--set-list", "no cases: give --set-list, --grid or --sweeps");
  if (lists) return cases_from_lists(options);
  if (load_scene_document(options.sweeps_file).root["cases"].IsDefined()) return cases_from_file(options.sweeps_file, baseline);
  const StabilityPlan plan = read_stability_plan(options.sweeps_file);
  if (baseline) *baseline = plan.baseline;
  std::vector<SweepCase> cases;
  for (const StabilitySweep& sweep : plan.sweeps)
    for (const std::string& value : sweep.values)
      for (const std::string& integrator : sweep.integrators)
        cases.push_back({{sweep.key + "=" + value, "integrator.type=" + integrator},
                         {{plan.file, sweep.line, "sweeps." + sweep.name + ".key"},
                          {plan.file, sweep.line, "sweeps." + sweep.name + ".integrators"}}});
  return cases;
}

std::string case_folder_name(std::size_t index) {
  char name[32];
  std::snprintf(name, sizeof name, "case-%04zu", index + 1);
  return name;
}

SweepStudy run_sweep(const SweepOptions& options, const std::function<void(const SweepRow&)>& on_row,
                     StudyRunner& runner) {
  const auto start = std::chrono::steady_clock::now();
  load_scene(options.scene_file, options.overrides);  // the user's own mistakes first, named as such
  SweepStudy study;
  const std::vector<SweepCase> cases = sweep_cases(options, &study.baseline);
  std::vector<std::string> common = options.overrides;
  common.insert(common.end(), study.baseline.begin(), study.baseline.end());
  std::unique_ptr<Scene> scene;
  try {
    scene = load_scene(options.scene_file, common);
  } catch (const SceneError& e) {
    throw SceneError(options.sweeps_file, 0, "baseline", std::string("the scene rejects it: ") + e.what());
  }
  check_case_keys(*scene, cases);
  study.scene_name = scene->name;
  study.scene_file = options.scene_file;
  study.sweeps_file = options.sweeps_file;
  study.description = scene->description;
  study.overrides = options.overrides;
  study.placement = runner.placement().text();
  study.case_outputs = !options.case_directory.empty();
  auto run_case = [&](std::size_t index) {
    std::vector<std::string> overrides = common;
    overrides.insert(overrides.end(), cases[index].settings.begin(), cases[index].settings.end());
    const std::string directory = options.case_directory.empty()
                                      ? std::string()
                                      : (std::filesystem::path(options.case_directory) / case_folder_name(index)).string();
    SweepRow row = run_one(options.scene_file, overrides, directory, options.case_directory,
                           options.shown_directory.empty() ? options.case_directory : options.shown_directory);
    row.settings = cases[index].settings;
    return row_record(row);
  };
  auto take = [&](std::size_t, const std::string& record) {
    SweepRow row = read_row(record);
    if (on_row) on_row(row);
    study.rows.push_back(std::move(row));
  };
  runner.run(cases.size(), run_case, take);
  study.total_wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return study;
}

}  // namespace csim
