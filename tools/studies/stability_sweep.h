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

enum class StabilityOutcome { passed, check_failed, stopped, bad_input };
const char* outcome_name(StabilityOutcome outcome);  // "passed", "check failed", "stopped", "bad input"

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
  std::vector<StabilityRow> rows;
  double total_wall_time = 0.0;         // s, the whole study as the clock on the wall saw it
  bool invariants_hold() const {
    for (const StabilityRow& r : rows)
      if (r.violates_invariant()) return false;
    return true;
  }
};

// Runs the study. Throws SceneError for a scene that does not load with the user's overrides, a bad
// sweeps file, an unknown --only sweep, a baseline the scene rejects or a sweep key the scene does not
// have; every failure of one case (a value the scene rejects included) becomes its row.
// on_row is called after each run, in order. A stop request (stop_request.h) ends the study with
// StopRequested, between runs or at a step of one.
StabilityStudy run_stability_sweep(const StabilityOptions& options, const std::function<void(const StabilityRow&)>& on_row = {});

// stability.md (one table per sweep) and stability.csv (one row per run), written atomically.
std::string stability_markdown(const StabilityStudy& study);
std::string stability_csv(const StabilityStudy& study);
void write_stability_markdown(const StabilityStudy& study, const std::string& directory);
void write_stability_csv(const StabilityStudy& study, const std::string& directory);

}  // namespace csim
