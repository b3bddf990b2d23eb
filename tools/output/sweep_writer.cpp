#include "tools/output/sweep_writer.h"

#include "tools/output/atomic_file.h"
#include "tools/output/csv_text.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace csim {

namespace {

std::string exact(double x) {
  if (std::isnan(x)) return "";
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, x).ptr);
}

std::string join(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : " ") + item;
  return text.empty() ? "none" : text;
}

std::string key_of(const std::string& setting) { return setting.substr(0, setting.find('=')); }

}  // namespace

std::string sweep_csv(const SweepStudy& study) {
  std::vector<std::string> keys, checks;  // in the order the cases first give them
  for (const SweepRow& row : study.rows) {
    for (const std::string& setting : row.settings)
      if (std::find(keys.begin(), keys.end(), key_of(setting)) == keys.end()) keys.push_back(key_of(setting));
    for (const SweepCheck& check : row.checks)
      if (std::find(checks.begin(), checks.end(), check.name) == checks.end()) checks.push_back(check.name);
  }
  std::ostringstream csv;
  csv << "# csim sweep: parameter study of scene " << study.scene_name << " (" << study.scene_file << ")\n";
  if (!study.sweeps_file.empty()) csv << "# sweeps: " << study.sweeps_file << "\n";
  csv << "# overrides: " << join(study.overrides) << "; baseline: " << join(study.baseline) << "\n"
      << "# placement: " << study.placement << "\n"
      << "# each case runs as `csim run --set OVERRIDES --set BASELINE --set KEY=VALUE...` would"
      << (study.case_outputs ? ", its outputs in case-NNNN/ (NNNN = case)" : "") << "\n"
      << "# exit_status: as csim run (0 checks passed or none declared, 1 not a pass, 2 bad input, a numerical failure or an "
         "environment failure: status says which); "
         "steps: time steps (IDA: internal steps); contact_solves, solver_sweeps, not_converged, max_residual: "
         "the contact solver's over the run; newton_*: total and most in a step\n"
      << "# C, C_verdict per check C: its value (empty when not evaluated) and passed | failed | not evaluated | "
         "excluded; wall_time (s): the time loop, or load and run until a failure\n";
  csv << "case";
  for (const std::string& key : keys) csv << ',' << csv_field(key);
  csv << ",exit_status,status,message,end_time,steps,contact_solves,solver_sweeps,not_converged,max_residual,"
         "newton_iterations,newton_max";
  for (const std::string& check : checks) csv << ',' << csv_field(check) << ',' << csv_field(check + "_verdict");
  csv << ",wall_time\n";
  for (std::size_t index = 0; index < study.rows.size(); ++index) {
    const SweepRow& row = study.rows[index];
    csv << index + 1;
    for (const std::string& key : keys) {
      std::string value;
      for (const std::string& setting : row.settings)
        if (key_of(setting) == key) value = setting.substr(key.size() + 1);
      csv << ',' << csv_field(value);
    }
    const bool ran = row.steps >= 0;
    csv << ',' << row.exit_status << ',' << row.status << ',' << csv_field(row.message) << ',' << exact(row.end_time)
        << ',' << (ran ? std::to_string(row.steps) : "");
    for (long n : {row.contact_solves, row.solver_sweeps, row.not_converged}) csv << ',' << (ran ? std::to_string(n) : "");
    csv << ',' << (ran ? exact(row.max_residual) : "");
    for (long n : {row.newton_iterations, row.newton_max}) csv << ',' << (ran ? std::to_string(n) : "");
    for (const std::string& name : checks) {
      const auto check = std::find_if(row.checks.begin(), row.checks.end(),
                                      [&](const SweepCheck& c) { return c.name == name; });
      if (check == row.checks.end()) csv << ",,";
      else csv << ',' << exact(check->value) << ',' << check->verdict;
    }
    csv << ',' << exact(row.wall_time) << '\n';
  }
  return csv.str();
}

void write_sweep_csv(const SweepStudy& study, const std::string& directory) {
  std::filesystem::create_directories(directory);
  write_file_atomically((std::filesystem::path(directory) / "sweep.csv").string(), sweep_csv(study));
}

}  // namespace csim
