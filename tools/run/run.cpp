#include "tools/run/run.h"

#include "tools/output/atomic_file.h"
#include "tools/output/body_poses.h"
#include "tools/output/json_writer.h"
#include "tools/output/paraview_series.h"
#include "tools/output/vtk_writer.h"
#include "tools/run/probes.h"
#include "tools/scene/scene_error.h"
#include "tools/run/stop_request.h"
#include "engine/steppers/generalized_alpha.h"
#include "engine/steppers/ida_integrator.h"
#include "engine/steppers/moreau_jean.h"
#include "engine/steppers/quasi_static.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace csim {

namespace {

void append_row(std::ostringstream& csv, double t, const std::vector<double>& values, RunReport& report) {
  report.sample_times.push_back(t);
  report.samples.push_back(values);
  csv << t;
  for (double v : values) csv << ',' << v;
  csv << '\n';
}

class Progress {
 public:
  explicit Progress(bool enabled) : enabled_(enabled), start_(Clock::now()), last_(start_) {}
  void update(double t, double end) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - last_).count() < 1.0 ||
        std::chrono::duration<double>(now - start_).count() < 2.0)
      return;
    last_ = now;
    shown_ = true;
    std::fprintf(stderr, "\r  t = %.6g / %.6g s (%3.0f %%)", t, end, 100.0 * t / end);
    std::fflush(stderr);
  }
  ~Progress() {
    if (shown_) std::fprintf(stderr, "\r%60s\r", "");
  }

 private:
  using Clock = std::chrono::steady_clock;
  bool enabled_, shown_ = false;
  Clock::time_point start_, last_;
};

// Rows of probes.csv, and so ParaView frames, a run writes at most: the first, then at most one per step
// and one per output interval, and the last.
std::size_t output_rows(const RunSettings& run) {
  const double intervals = std::ceil(run.end_time / std::max(run.output_rate, run.step));
  return static_cast<std::size_t>(std::min<double>(run.steps, intervals + 1.0)) + 1;
}

}  // namespace

void check_outputs(const Scene& scene) {
  if (!scene.run.paraview) return;  // output.paraview: none
  const auto problem = paraview_name_problem(scene.world, output_rows(scene.run), scene.run.shapes);
  if (!problem) return;
  int line = 0;  // of the body's name
  for (const auto& entry : scene.document.root["bodies"])
    if (entry.first.as<std::string>() == problem->body) line = entry.first.Mark().line + 1;
  throw SceneError(scene.document.file, line, "bodies." + problem->body, problem->message);
}

State initial_state(const World& world) {
  State state;
  state.q.setZero(world.position_size);
  state.v.setZero(world.velocity_size);
  for (const BodyInstance& b : world.bodies) {
    if (b.body->fixed()) continue;
    state.q.segment(b.position_offset, b.body->position_size()) = b.initial_position;
    state.v.segment(b.velocity_offset, b.body->velocity_size()) = b.initial_velocity;
  }
  return state;
}

std::unique_ptr<Stepper> make_stepper(const World& world, const RunSettings& run) {
  try {
    switch (run.integrator) {
      case Integrator::ida:
      case Integrator::ida_events: return std::make_unique<IdaIntegrator>(world, ida_parameters(run));
      case Integrator::quasi_static: return std::make_unique<QuasiStatic>(world, quasi_static_parameters(run));
      case Integrator::generalized_alpha:
        return std::make_unique<GeneralizedAlpha>(world, generalized_alpha_parameters(run));
      case Integrator::moreau_jean: break;
    }
    return std::make_unique<MoreauJean>(world, moreau_jean_parameters(run));
  } catch (const RunError& e) {  // before the first step: what the stepper cannot run, not a numerical failure
    throw std::invalid_argument(e.what());
  }
}

RunReport run_scene(const Scene& scene, const RunOptions& options) {
  const RunSettings& run = scene.run;
  if (!options.output_directory.empty()) check_outputs(scene);
  // An earlier run's outputs in the same folder must not mix with this run's, nor pass for them when it
  // fails before its first step (it then writes nothing).
  if (!options.output_directory.empty()) {
    const std::filesystem::path dir(options.output_directory);
    std::filesystem::remove(dir / "probes.csv");
    std::filesystem::remove(dir / "bodies.csv");
    std::filesystem::remove(dir / "summary.json");
    remove_paraview_outputs(options.output_directory);
  }
  const std::unique_ptr<Stepper> stepper_owner = make_stepper(scene.world, run);
  Stepper& stepper = *stepper_owner;
  ProbeEvaluator probes(scene.world, run);
  CheckEvaluator checks(run, scene.document.scope);
  ContactClosings closings;
  RunReport report;
  State& state = report.state;
  state = initial_state(scene.world);
  stepper.initialize(state);

  std::ostringstream csv;
  csv << std::setprecision(15) << 't';
  for (const ProbeDefinition& p : run.probes) csv << ',' << p.name;
  csv << '\n';

  const double h = run.step;
  const long steps = run.steps;
  const double rate = std::max(run.output_rate, h);
  // ParaView frames of the elastic bodies and of the shapes (output.shapes), at the rows of probes.csv
  // (docs/contract.md).
  std::unique_ptr<ParaviewSeries> paraview;
  if (!options.output_directory.empty() && run.paraview && (has_elastic_bodies(scene.world) || run.shapes))
    paraview = std::make_unique<ParaviewSeries>(scene.world, options.output_directory, *run.paraview,
                                                // The quasi-static stepper's impulses are forces × h.
                                                ContactAction{run.integrator == Integrator::quasi_static, run.step},
                                                run.shapes);
  // The moving bodies' poses at the same rows (output.bodies).
  std::unique_ptr<BodyPoses> poses;
  if (!options.output_directory.empty() && run.body_poses) poses = std::make_unique<BodyPoses>(scene.world);
  const auto output_row = [&](const std::vector<double>& row) {
    append_row(csv, state.t, row, report);
    if (paraview) paraview->write_frame(scene.world, state, state.t);
    if (poses) poses->add_frame(scene.world, state);
  };
  std::vector<double> values;
  probes.evaluate(state, values);
  checks.add_sample(state.t, values);
  output_row(values);
  double next_output = rate;

  const bool energy_probes = probes.reads_energy();
  const std::vector<int>& sampled = checks.sampled_probes();
  const bool every_probe_sampled = sampled.size() == run.probes.size();
  Progress progress(options.progress);
  const auto start = std::chrono::steady_clock::now();
  long k = 0;  // the steps done; the one under way when a RunError is thrown is k + 1
  const auto write_outputs = [&] {
    if (options.output_directory.empty()) return;
    std::filesystem::create_directories(options.output_directory);
    const std::filesystem::path dir(options.output_directory);
    write_file_atomically((dir / "probes.csv").string(), csv.str());
    if (poses) write_file_atomically((dir / "bodies.csv").string(), poses->text());
    write_file_atomically((dir / "summary.json").string(), summary_json(scene, report));
    if (paraview) paraview->finish();
  };
  try {
    for (; k < steps; ++k) {
      honour_stop_request();
      stepper.step(state);
      if (energy_probes) stepper.measure_energy(state);
      // A step that closed a contact may hold an impact's jump: no extremum's parabola, no interpolation
      // at a time spans it (checks.h).
      const bool closed = checks.reads_jumps() && closings.closed(state.contacts);
      // Events inside the step (stick/slip switches of ida-events) are exact samples.
      for (const EventSample& event : state.events) {
        State at_event = state;
        at_event.t = event.t;
        at_event.q = event.q;
        at_event.v = event.v;
        probes.evaluate(at_event, values);
        checks.add_sample(event.t, values, true, closed);
      }
      // Between output rows, only the probes whose every sample a check reads (CheckEvaluator::
      // sampled_probes); an output row, and so the last step, has every probe's value.
      const bool row = state.t >= next_output - 0.5 * h || k + 1 == steps;
      if (row || every_probe_sampled) probes.evaluate(state, values);
      else probes.evaluate(state, values, sampled);
      checks.add_sample(state.t, values, false, closed);
      if (row) {
        output_row(values);
        while (next_output <= state.t + 0.5 * h) next_output += rate;
      }
      progress.update(state.t, run.end_time);
    }
  } catch (const RunError& e) {
    // What was computed up to the failure stays: the rows and frames written, and a summary that says
    // where and why the run stopped and whose checks are not judged (the run did not reach its end).
    report.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    report.failure = RunFailure{e.time, k + 1, report.sample_times.back(), e.what()};
    report.checks = unjudged_checks(run, e.time);
    stepper.summarize_settings(report.stepper_settings);
    stepper.summarize_statistics(state, report.stepper_statistics);
    report.energy_balance_tracked = stepper.tracks_energy_balance();
    write_outputs();
    throw;
  }
  stepper.measure_energy(state);  // for the summary
  report.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report.checks = checks.finish(state.t);
  stepper.summarize_settings(report.stepper_settings);
  stepper.summarize_statistics(state, report.stepper_statistics);
  report.energy_balance_tracked = stepper.tracks_energy_balance();
  write_outputs();
  return report;
}

std::string summary_json(const Scene& scene, const RunReport& report) {
  const State& s = report.state;
  const SolverCounters& c = s.counters;
  const RunSettings& run = scene.run;
  JsonWriter json;
  json.begin_object();
  json.value("scene", scene.name).value("file", scene.document.file);
  json.value("status", report.failure ? "failed" : "completed");
  if (const std::optional<RunFailure>& f = report.failure)
    json.begin_object("failure")
        .value("time", f->time).value("step", f->step).value("last_row_time", f->last_row_time)
        .value("reason", f->reason)
        .end_object();
  json.value("integrator", integrator_name(run.integrator));
  json.entries(report.stepper_settings);
  json.value("dimension", scene.world.dimension);
  json.value("time_step", run.step).value("requested_time_step", run.requested_step);
  json.value("end_time", run.end_time);
  json.value("steps", c.steps).value("wall_time", report.wall_time);
  json.value("steps_per_second", report.wall_time > 0 ? c.steps / report.wall_time : 0.0);
  json.begin_object("contact_solver")
      .value("method", "projected Gauss-Seidel")
      .value("tolerance", run.contact_solver.tolerance)
      .value("max_iterations", run.contact_solver.max_iterations)
      .value("solves", c.solves)
      .value("total_iterations", c.total_iterations)
      .value("mean_iterations", c.solves > 0 ? double(c.total_iterations) / c.solves : 0.0)
      .value("max_iterations_used", c.max_iterations)
      .value("not_converged", c.not_converged)
      .value("first_not_converged_time", c.first_not_converged_time)
      .value("max_residual", c.max_residual)
      .value("rejected_local_solutions", c.rejected_local_solutions)
      .value("cold_restarts", c.cold_restarts)
      .value("sweeps_only_retries", c.sweeps_only_retries)
      .end_object();
  json.entries(report.stepper_statistics);
  json.begin_object("contacts")
      .value("max_active", c.max_contact_points)
      .value("mean_active", c.steps > 0 ? double(c.contact_points) / c.steps : 0.0)
      .value("active_at_end", static_cast<long>(s.contacts.size()))
      .value("deepest_penetration", c.deepest_penetration)
      .end_object();
  const EnergyBalance& e = s.energy;
  const double scale = std::max({std::abs(e.initial_kinetic) + std::abs(e.initial_elastic),
                                 std::abs(e.work_of_loads), std::abs(e.kinetic) + std::abs(e.elastic), 1e-300});
  // A stepper that stores only the elastic energy (quasi-static: no work of prescribed motions, no
  // friction dissipation) writes no balance: it would read the elastic energy as a residual.
  const bool balance = report.energy_balance_tracked;
  json.begin_object("energy")
      .value("kinetic", e.kinetic).value("elastic", e.elastic)
      .value("initial_kinetic", e.initial_kinetic).value("initial_elastic", e.initial_elastic)
      .value("balance_tracked", balance);
  if (balance)
    json.value("work_of_loads", e.work_of_loads)
        .value("contact_dissipation", e.contact_dissipation)
        .value("numerical_dissipation", e.numerical_dissipation)
        .value("damping_dissipation", e.damping_dissipation)
        .value("sleep_dissipation", e.sleep_dissipation)
        .value("balance_residual", e.residual())
        .value("max_abs_balance_residual", e.max_abs_residual)
        .value("relative_balance_residual", e.max_abs_residual / scale);
  json.end_object();
  json.begin_object("timers")
      .value("free_velocity", s.timers.free_velocity).value("detection", s.timers.detection)
      .value("assembly", s.timers.assembly).value("solve", s.timers.solve).value("update", s.timers.update)
      .end_object();
  json.begin_array("checks");
  for (const CheckResult& r : report.checks) {
    json.begin_object()
        .value("name", r.name).value("probe", r.probe).value("kind", r.kind).value("source", r.source)
        .value("time", r.time).value("reference", r.reference).value("value", r.value)
        .value("error", r.error)
        .value("relative_error", r.reference != 0.0 ? r.error / std::abs(r.reference) : 0.0);
    json.begin_object("tolerance")
        .value("absolute", r.absolute_tolerance).value("relative", r.relative_tolerance).end_object();
    json.value("passed", r.passed).value("skipped", r.skipped).value("evaluated", r.evaluated);
    if (!r.note.empty()) json.value("note", r.note);
    json.end_object();
  }
  json.end_array();
  const CheckCounts counts = report.counts();
  json.begin_object("check_counts")
      .value("passed", counts.passed).value("failed", counts.failed)
      .value("not_evaluated", counts.not_evaluated).value("excluded", counts.excluded)
      .end_object();
  json.value("passed", report.passed());
  json.value("plain_simulation", report.plain_simulation());
  json.end_object();
  return json.str();
}

}  // namespace csim
