// The work-precision study behind `csim compare` (DESIGN.md §4): one scene run with each integrator over
// a list of time steps (moreau-jean) or tolerances (ida, ida-events), each configuration repeated to
// take the median wall time, and the error of every analytical or literature check against the
// scene's own reference. Errors of one run (an integrator not built yet, a numerical failure) are
// recorded in its row and the study goes on.
#pragma once

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

// A check whose error the study measures: enabled for these parameters, kind analytical or literature.
struct ComparedCheck {
  std::string name, kind, source;
  std::string reference;                // the expression or number of the scene file
  double reference_value = 0.0;         // as evaluated by the first successful run
  bool reference_known = false;
};

// One configuration (integrator and step or tolerance). Errors are NaN where a run could not evaluate
// the check (e.g. fewer extrema than asked), and for failed runs.
struct CompareRow {
  std::string integrator;
  std::string parameter;                // time.step or integrator.rtol (= atol)
  double value = 0.0;
  std::vector<double> wall_times;       // s, one per repeat that ran
  double wall_time_median = 0.0;        // s
  long steps = 0;
  long solver_iterations = 0;
  bool ok = false;
  std::string failure;                  // the message when !ok
  double max_rel_error = 0.0;           // over the analytical checks (or, against a reference run, the
                                        // largest max_t |p − p_ref| / max_t |p_ref| over the probes)
  std::vector<double> errors, relative_errors;  // per ComparedCheck, |value − reference| and / |reference|
  std::vector<std::string> not_evaluated;  // checks the run could not evaluate (their errors are NaN)
};

struct Comparison {
  std::string scene_name, scene_file, description;
  std::string reference;                // what the errors are measured against, in words (the CSV says it)
  bool trajectory_reference = false;    // errors are deviations of the probe histories from a reference run
  std::vector<std::string> overrides;
  std::vector<ComparedCheck> checks;
  std::vector<CompareRow> rows;
  bool all_ok() const {
    for (const CompareRow& r : rows)
      if (!r.ok) return false;
    return true;
  }
};

// The integrator names --integrators accepts.
const std::vector<std::string>& comparable_integrators();

// Runs the study. Throws SceneError for bad options (unknown integrator, empty or non-positive lists,
// repeats < 1) or when the scene does not load with the user's overrides alone; every other failure
// becomes a failed row. on_row is called after each configuration, in order, to report progress.
// A stop request (stop_request.h) ends the study with StopRequested, between runs or at a step of one.
Comparison run_comparison(const CompareOptions& options,
                          const std::function<void(const CompareRow&)>& on_row = {});

// work_precision.csv: '#' lines (scene, overrides, each check's kind, reference and source), a header
// row, one row per configuration. Columns: integrator, parameter, value, wall_time_median, wall_times,
// steps, solver_iterations, status, max_rel_error, then C_error, C_rel_error per check.
std::string work_precision_csv(const Comparison& comparison);
void write_work_precision_csv(const Comparison& comparison, const std::string& directory);

// work_precision.gp: max_rel_error against median wall time, log-log, one line per integrator, points
// labelled by step or tolerance; the data are inlined so the script runs on its own from `directory`.
std::string gnuplot_script(const Comparison& comparison);
void write_gnuplot_script(const Comparison& comparison, const std::string& directory);

// Runs `gnuplot work_precision.gp` in `directory`. Never throws: a missing gnuplot or a failed plot is
// reported as a value so that the caller can warn and carry on with the CSV.
struct PlotOutcome {
  bool produced = false;
  std::string message;                  // why not, when !produced
};
PlotOutcome plot_work_precision(const Comparison& comparison, const std::string& directory);

}  // namespace csim
