// The table of `csim sweep` and its writer: one row per case, with its settings, its exit status as
// `csim run` would give it, its summary figures and its checks. The study (tools/studies/sweep.h) fills a
// SweepStudy; nothing here runs a scene.
#pragma once

#include <string>
#include <vector>

namespace csim {

// One check of one case, as summary.json has it.
struct SweepCheck {
  std::string name;
  double value = 0.0;                   // the probe's value (NaN when not evaluated)
  std::string verdict;                  // passed | failed | not evaluated | excluded (by its only_if)
};

struct SweepRow {
  std::vector<std::string> settings;    // the case's own KEY=VALUE
  int exit_status = 2;                  // as `csim run`: 0 pass or no checks, 1 not a pass, 2 any failure below
  // passed | no checks (a plain simulation run to its end) | not a pass | bad input | numerical failure | environment failure (out of memory, a file that
  // cannot be written: tools/studies/case_failure.h)
  std::string status;
  std::string message;                  // the error of a bad-input or failed case; the verdict otherwise
  double end_time = 0.0;                // s, the time reached
  long steps = -1;                      // time steps (IDA: internal steps); −1 when the case did not run
  long contact_solves = 0, solver_sweeps = 0, not_converged = 0;  // the contact solver's, summed over the run
  double max_residual = 0.0;            // the contact solver's largest final residual
  long newton_iterations = 0, newton_max = 0;  // quasi-static and finite-strain steppers: total, most in a step
  std::vector<SweepCheck> checks;
  double wall_time = 0.0;               // s: the time loop, or load + run until the failure
};

struct SweepStudy {
  std::string scene_name, scene_file, sweeps_file, description;
  std::vector<std::string> overrides, baseline;
  std::string placement = "serial (1 process)";  // study_runner.h: Placement
  bool case_outputs = false;            // whether each case wrote its folder case-NNNN
  std::vector<SweepRow> rows;
  double total_wall_time = 0.0;         // s
  bool all_passed() const {
    for (const SweepRow& r : rows)
      if (r.exit_status != 0) return false;
    return true;
  }
};

// sweep.csv: '#' lines (scene, overrides, baseline, placement, the columns' meaning), a header row, one row
// per case. Columns: case, one per key set by some case (its value, empty when the case does not set it),
// exit_status, status, message, end_time, steps, contact_solves, solver_sweeps, not_converged,
// max_residual, newton_iterations, newton_max, then C and C_verdict per check C (in the order the cases
// first give them), and wall_time last. Numbers are the shortest text that reads back as the same double.
std::string sweep_csv(const SweepStudy& study);
void write_sweep_csv(const SweepStudy& study, const std::string& directory);

}  // namespace csim
