// The parameter study behind `csim sweep` (docs/contract.md): one scene run once per case, a case being a
// set of KEY=VALUE overrides, each run exactly as `csim run --set ...` would run it. The cases come from
//   --set-list KEY=V1,V2,...   lists taken together: case i sets the i-th value of every list;
//   --grid KEY=V1,V2,...       every combination, the first grid key varying slowest;
// (lists and grids together: every list case with every grid combination), or from a sweeps file: in the
// format of `csim stress` (stability_sweep.h), its baseline for every case, then each sweep's key and
// value with each of its integrators; or a list of explicit cases, each its own KEY=VALUE list:
//   baseline: [output.rate=0]                       # optional, every case
//   cases: [[parameters.mu=0.02, parameters.element=quad4], [parameters.mu=0.2]] A failed case is a row with its message; the study goes on.
#pragma once

#include "tools/output/sweep_writer.h"
#include "tools/studies/study_runner.h"

#include <functional>
#include <string>
#include <vector>

namespace csim {

struct SweepOptions {
  std::string scene_file;               // a scene.yaml (not a folder)
  std::vector<std::string> overrides;   // the user's KEY=VALUE, applied to every case before its own
  std::vector<std::string> set_lists;   // KEY=V1,V2,...
  std::vector<std::string> grids;       // KEY=V1,V2,...
  std::string sweeps_file;              // a stress.yaml-like file; exclusive with set_lists and grids
  // Where each case writes what `csim run --out` would (case-0001/, case-0002/, ...); empty: nothing.
  std::string case_directory;
  // The folder that messages name for case_directory: the one the user asked for, where case_directory is
  // the temporary folder that replaces it at the end (output_folder.h). Empty: case_directory itself.
  std::string shown_directory;
};

// Where a case's setting was given, for the message that refuses its key: the file (the scene file for
// --set-list and --grid), its line (0: none) and the key path or option there.
struct SettingOrigin {
  std::string file;
  int line = 0;
  std::string path;                     // --set-list, --grid, cases, sweeps.NAME.key, ...
};

// The cases, in study order. Throws SceneError for a malformed or empty list, lists of different
// lengths, a key given twice, or a sweeps file together with lists.
struct SweepCase {
  std::vector<std::string> settings;    // KEY=VALUE, the case's own
  std::vector<SettingOrigin> origins;   // one per setting
};
std::vector<SweepCase> sweep_cases(const SweepOptions& options, std::vector<std::string>* baseline = nullptr);

// The folder name of case `index` (0-based): case-0001 for the first.
std::string case_folder_name(std::size_t index);

// Runs the study. Throws SceneError for bad options, when the scene does not load with the user's
// overrides and the baseline, or when a case sets a key that --set could not replace (case_keys.h),
// all before the first case; every other failure of one case (a value the scene rejects included)
// becomes its row. on_row is called on the root
// after each case, in case order.
SweepStudy run_sweep(const SweepOptions& options, const std::function<void(const SweepRow&)>& on_row = {},
                     StudyRunner& runner = serial_runner());

}  // namespace csim
