// Running a loaded scene end to end: the time loop, probes sampled every step, checks evaluated,
// and the outputs of docs/contract.md (summary.json, probes.csv) written to the output folder.
#pragma once

#include "tools/run/checks.h"
#include "tools/scene/scene.h"
#include "engine/state.h"
#include "engine/steppers/stepper.h"

#include <memory>
#include <string>
#include <vector>

namespace csim {

struct RunOptions {
  std::string output_directory;  // empty: write nothing
  bool progress = false;         // progress line on stderr for runs longer than ~2 s
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
  CheckCounts counts() const { return count_checks(checks); }
  bool passed() const { return counts().pass(); }  // checks.h: CheckCounts::pass
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

// Throws RunError on a numerical failure (no output file is left half-written), StopRequested at the
// first step boundary after a stop request (stop_request.h).
RunReport run_scene(const Scene& scene, const RunOptions& options);

// The summary.json text of a finished run.
std::string summary_json(const Scene& scene, const RunReport& report);

}  // namespace csim
