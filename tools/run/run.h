// Running a loaded scene end to end: the time loop, probes sampled every step, checks evaluated,
// and the outputs of docs/contract.md (summary.json, probes.csv) written to the output folder.
#pragma once

#include "tools/run/checks.h"
#include "tools/scene/scene.h"
#include "engine/state.h"
#include "engine/steppers/stepper.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace csim {

struct RunOptions {
  std::string output_directory;  // empty: write nothing
  bool progress = false;         // progress line on stderr for runs longer than ~2 s
};

// Where and why a run stopped before its end (a RunError of the stepper).
struct RunFailure {
  double time = 0.0;   // s, the RunError's time: the end of the step that failed
  long step = 0;       // that step of time.step, counted from 1
  double last_row_time = 0.0;  // s, the last row of probes.csv (and ParaView frame) written before it
  std::string reason;  // the RunError's message
};

struct RunReport {
  State state;                   // final state
  std::vector<CheckResult> checks;
  std::vector<double> sample_times;               // s, the rows of probes.csv
  std::vector<std::vector<double>> samples;       // probe values at those times
  double wall_time = 0.0;        // s
  // The stepper's part of the summary (summary_entries.h), taken at the end of the run.
  SummaryEntries stepper_settings, stepper_statistics;
  bool energy_balance_tracked = true;  // Stepper::tracks_energy_balance
  std::optional<RunFailure> failure;   // set when the run stopped on a RunError
  CheckCounts counts() const { return count_checks(checks); }
  bool passed() const { return !failure && counts().pass(); }  // checks.h: CheckCounts::pass
  // A scene that declares no check, run to its end: a simulation, not a verification. Its `passed` is
  // false (nothing was judged) and `csim run` exits 0 (docs/contract.md). A scene whose checks are all
  // excluded by their only_if is not one: it was meant to be judged and could not be.
  bool plain_simulation() const { return !failure && checks.empty(); }
};

// The state at t = 0: every body at its initial position and velocity.
State initial_state(const World& world);

// The stepper of the settings' integrator for a World, built (its checks of what it can run done) but
// not started. Throws std::invalid_argument for what it cannot run.
std::unique_ptr<Stepper> make_stepper(const World& world, const RunSettings& run);

// What the output writers would refuse, checked before the first step by run and by validate alike:
// ParaView file names of the elastic bodies that collide or are too long (vtk_writer.h). Throws
// SceneError naming the scene file, the body's line and its key path.
void check_outputs(const Scene& scene);

// Throws RunError on a numerical failure, after writing what was computed up to it (no file is left
// half-written): the rows of probes.csv and the ParaView frames before the failing step, and a
// summary.json whose `status` is "failed", with the `failure`'s time, step and reason and every check not
// evaluated (docs/contract.md). Throws StopRequested at the first step boundary after a stop request
// (stop_request.h), writing nothing.
RunReport run_scene(const Scene& scene, const RunOptions& options);

// The summary.json text of a run: finished (`status` "completed") or stopped by a numerical failure
// (`status` "failed").
std::string summary_json(const Scene& scene, const RunReport& report);

}  // namespace csim
