// The stability table of `csim stress` and its writers: one row per case and integrator, with its
// outcome, its worst check and Moreau–Jean's energy invariants, as Markdown and CSV. The sweep
// (tools/studies/stability_sweep.h) fills a StabilityStudy; nothing here runs a scene.
#pragma once

#include <string>
#include <vector>

namespace csim {

// environment_failure: out of memory or the like (tools/studies/case_failure.h), the machine's failure
// and not the scene's; the invariants are then unverified, which counts as a violation.
enum class StabilityOutcome { passed, check_failed, stopped, bad_input, environment_failure };
// "passed", "check failed", "stopped", "bad input", "environment failure"
const char* outcome_name(StabilityOutcome outcome);

// Moreau–Jean's energy invariants, thresholds relative to the run's energy scale
// max(|W_loads|, E_kinetic + E_elastic, their initial sum, 1e-300).
constexpr double kCreatedEnergyTolerance = 1e-9;  // contact and numerical dissipation ≥ −tol·scale
constexpr double kBalanceTolerance = 1e-6;        // worst |balance residual| ≤ tol·scale

struct StabilityRow {
  std::string sweep, key, value, integrator;
  StabilityOutcome outcome = StabilityOutcome::bad_input;
  // The worst check: relative error, or absolute where the reference is 0; among the failed checks
  // when some failed. NaN with a name when that check could not be evaluated; empty name: no check.
  double worst_error = 0.0;
  bool worst_error_relative = true;
  std::string worst_check;
  std::vector<std::string> failed_checks;
  // Energy (J) of the final state; judged for moreau-jean only (IDA's penalty springs store energy
  // that the balance does not count).
  bool energy_judged = false;
  double contact_dissipation = 0.0, numerical_dissipation = 0.0, max_abs_residual = 0.0, energy_scale = 0.0;
  bool creates_energy = false, balance_open = false;
  std::vector<std::string> non_finite;  // what was not finite in the final state
  double wall_time = 0.0;               // s: RunReport::wall_time; for a failed run, load and run until it stopped
  long steps = -1;                      // moreau-jean: time steps; ida: IDA's internal steps; −1: unknown
  double stopped_at = 0.0;              // s, the RunError's time
  std::string message;                  // the error of a stopped or bad-input run

  std::string case_name() const { return key + "=" + value; }
  std::string energy_verdict() const;   // ok | creates energy X J | balance residual X J | not judged
  std::string worst_error_text() const; // e.g. "3.1e-02 rel (first_extremum)"
  std::string note() const;             // failed checks, message, non-finite values, the violation
  bool violates_invariant() const;
};

struct StabilityStudy {
  std::string scene_name, scene_file, sweeps_file, description;
  std::vector<std::string> overrides, baseline;
  std::string placement = "serial (1 process)";  // how the runs were placed (study_runner.h: Placement)
  std::vector<StabilityRow> rows;
  double total_wall_time = 0.0;         // s, the whole study as the clock on the wall saw it
  bool invariants_hold() const {
    for (const StabilityRow& r : rows)
      if (r.violates_invariant()) return false;
    return true;
  }
};

// stability.md (one table per sweep) and stability.csv (one row per run), written atomically.
std::string stability_markdown(const StabilityStudy& study);
std::string stability_csv(const StabilityStudy& study);
void write_stability_markdown(const StabilityStudy& study, const std::string& directory);
void write_stability_csv(const StabilityStudy& study, const std::string& directory);

}  // namespace csim
