// The stability study behind `csim stress`: one scene pushed over many decades of its
// parameters, one parameter at a time, with each integrator. A sweeps file (stress.yaml beside the
// scene by default) lists the cases:
//
//   baseline: [time.end=1]                 # KEY=VALUE overrides applied to every case
//   integrators: [moreau-jean, ida]        # the default list
//   sweeps:
//     mass: {key: parameters.mass, values: [1e-6, 1, 1e6]}
//     step: {key: time.step, values: [1e-5, 1e-2], integrators: [moreau-jean]}
//
// Each case (baseline + key=value) runs once per integrator (integrator.type=NAME). Accuracy is
// measured by the scene's own checks and only reported; what the study asserts are the invariants no
// setting may break: every value finite, every case a valid scene, and Moreau–Jean neither creating
// energy nor losing its discrete energy balance (state.h). IDA may stop with a clear RunError (too
// stiff, too many steps): that is an acceptable outcome, reported with its message.
#pragma once

#include "tools/output/stability_writer.h"
#include "tools/studies/study_runner.h"

#include <functional>
#include <string>
#include <vector>

namespace csim {

struct StabilityOptions {
  std::string scene_file;               // a scene.yaml (not a folder)
  std::string sweeps_file;              // empty: stress.yaml beside the scene file
  std::vector<std::string> overrides;   // the user's KEY=VALUE, applied before the study's own
  std::vector<std::string> only;        // names of the sweeps to run; empty: all
};

// One sweep of the file: key=value for each value, with each integrator.
struct StabilitySweep {
  std::string name, key;
  int line = 0;                         // of the key in the sweeps file
  std::vector<std::string> values;      // as written in the file, so that the override is exact
  std::vector<std::string> integrators;
};

struct StabilityPlan {
  std::string file;
  std::vector<std::string> baseline;
  int baseline_line = 0;
  std::vector<StabilitySweep> sweeps;      // in file order
};

// Reads a sweeps file strictly. Throws SceneError naming the file, the line and the key path.
StabilityPlan read_stability_plan(const std::string& file);

// Runs the study. Throws SceneError for a scene that does not load with the user's overrides, a bad
// sweeps file, an unknown --only sweep, a baseline the scene rejects or a sweep key the scene does not
// have; every failure of one case (a value the scene rejects included) becomes its row.
// on_row is called after each run, in order. A stop request (stop_request.h) ends the study with
// StopRequested, between runs or at a step of one.
// The runs are the cases of `runner` (study_runner.h): only the root's study holds rows.
StabilityStudy run_stability_sweep(const StabilityOptions& options, const std::function<void(const StabilityRow&)>& on_row = {},
                                   StudyRunner& runner = serial_runner());

}  // namespace csim
