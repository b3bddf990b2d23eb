// The work-precision table of `csim compare` and its writers: what one study measured (checks, and
// one row per integrator and step or tolerance), as CSV, as a gnuplot script and as a plot. The study
// (tools/studies/compare.h) fills a Comparison; nothing here runs a scene.
#pragma once

#include <string>
#include <vector>

namespace csim {

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
  std::string placement = "serial (1 process)";  // how the runs were placed (study_runner.h: Placement)
  std::vector<ComparedCheck> checks;
  std::vector<CompareRow> rows;
  bool all_ok() const {
    for (const CompareRow& r : rows)
      if (!r.ok) return false;
    return true;
  }
};

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
