// The work-precision study behind `csim compare` (docs/contract.md): one scene run with each integrator over
// a list of time steps (moreau-jean) or tolerances (ida, ida-events), each configuration repeated to
// take the median wall time, and the error of every analytical or literature check against the
// scene's own reference. Errors of one run (an integrator not built yet, a numerical failure) are
// recorded in its row and the study goes on.
#pragma once

#include "tools/output/work_precision_writer.h"
#include "tools/studies/study_runner.h"

#include <functional>
#include <string>
#include <vector>

namespace csim {

struct CompareOptions {
  std::string scene_file;               // a scene.yaml (not a folder)
  std::vector<std::string> overrides;   // the user's KEY=VALUE, applied to every run before the study's own
  std::vector<std::string> integrators; // moreau-jean, ida, ida-events
  std::vector<double> steps;            // s, time.step of the moreau-jean runs
  std::vector<double> tolerances;       // integrator.rtol = integrator.atol of the ida runs
  int repeats = 3;
  // The reference: analytical (the scene's analytical checks), ida-events (a converged event-driven run
  // at tolerance 1e-10), moreau-jean (a run at a step 100 times finer than the finest asked), or auto:
  // analytical when the scene has enabled analytical checks, else ida-events, else moreau-jean.
  std::string reference = "auto";
  std::string output_directory;         // empty: out/<scene>-compare (the caller resolves it from scene_name)
};

// The integrator names --integrators accepts.
const std::vector<std::string>& comparable_integrators();
// Their names in one line, "moreau-jean, generalized-alpha, ida, ida-events", for messages.
std::string comparable_integrator_names();

// Runs the study. Throws SceneError for bad options (unknown integrator, empty or non-positive lists,
// repeats < 1) or when the scene does not load with the user's overrides alone; every other failure
// becomes a failed row. on_row is called after each configuration, in order, to report progress.
// A stop request (stop_request.h) ends the study with StopRequested, between runs or at a step of one.
// The configurations are the cases of `runner` (study_runner.h); every rank loads the scene and runs the
// reference itself, and only the root's Comparison holds rows (and only there is on_row called).
Comparison run_comparison(const CompareOptions& options,
                          const std::function<void(const CompareRow&)>& on_row = {},
                          StudyRunner& runner = serial_runner());

}  // namespace csim
