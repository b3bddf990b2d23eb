// The outputs of `csim stress`: stability.md (a table per sweep, for people) and stability.csv (one
// row per run, for scripts), and the texts of a row both share with the command's own table.
#include "tools/output/atomic_file.h"
#include "tools/output/csv_text.h"
#include "tools/output/stability_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace csim {

namespace {

std::string number(double x, const char* format = "%.2e") {
  if (!std::isfinite(x)) return "";
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, format, x);
  return buffer;
}

std::string join(const std::vector<std::string>& items, const char* separator = ", ") {
  std::string out;
  for (const std::string& item : items) out += (out.empty() ? "" : separator) + item;
  return out;
}

std::string markdown_cell(const std::string& text) {
  std::string out;
  for (char c : one_line(text)) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out.empty() ? " " : out;
}

bool ran_to_the_end(const StabilityRow& row) {
  return row.outcome == StabilityOutcome::passed || row.outcome == StabilityOutcome::check_failed;
}

void write_markdown_table(std::ostringstream& md, const StabilityStudy& study, const std::string& sweep) {
  md << "| case | integrator | outcome | worst error | energy | wall time (s) | steps | note |\n"
        "|---|---|---|---|---|---:|---:|---|\n";
  for (const StabilityRow& row : study.rows) {
    if (row.sweep != sweep) continue;
    md << "| " << markdown_cell(row.case_name()) << " | " << row.integrator << " | " << outcome_name(row.outcome)
       << " | " << markdown_cell(row.worst_error_text()) << " | " << markdown_cell(row.energy_verdict()) << " | "
       << number(row.wall_time, "%.3g") << " | " << (row.steps >= 0 ? std::to_string(row.steps) : "-") << " | "
       << markdown_cell(row.note()) << " |\n";
  }
}

}  // namespace

std::string StabilityRow::worst_error_text() const {
  if (worst_check.empty()) return "-";
  if (std::isnan(worst_error)) return "not evaluated (" + worst_check + ")";
  return number(worst_error) + (worst_error_relative ? " rel (" : " abs (") + worst_check + ")";
}

std::string StabilityRow::energy_verdict() const {
  if (!ran_to_the_end(*this)) return "-";
  if (!energy_judged) return "not judged";
  std::vector<std::string> verdicts;
  if (creates_energy)
    verdicts.push_back("creates energy " + number(-std::min(contact_dissipation, numerical_dissipation)) + " J");
  if (balance_open) verdicts.push_back("balance residual " + number(max_abs_residual) + " J");
  return verdicts.empty() ? "ok" : join(verdicts, "; ");
}

std::string StabilityRow::note() const {
  std::vector<std::string> parts;
  if (violates_invariant()) parts.push_back("INVARIANT VIOLATED");
  if (!failed_checks.empty()) parts.push_back("failed: " + join(failed_checks));
  if (!non_finite.empty()) parts.push_back("not finite: " + join(non_finite));
  if (!message.empty()) parts.push_back(message);
  return join(parts, "; ");
}

std::string stability_markdown(const StabilityStudy& study) {
  std::ostringstream md;
  const long violations = std::count_if(study.rows.begin(), study.rows.end(),
                                        [](const StabilityRow& r) { return r.violates_invariant(); });
  md << "# Stability study of scene " << study.scene_name << "\n\n"
     << "Written by `csim stress` from `" << study.sweeps_file << "` on `" << study.scene_file << "`.\n\n"
     << "- baseline: " << (study.baseline.empty() ? "none" : "`" + join(study.baseline, "`, `") + "`") << "\n"
     << "- overrides: " << (study.overrides.empty() ? "none" : "`" + join(study.overrides, "`, `") + "`") << "\n"
     << "- " << study.rows.size() << " runs in " << number(study.total_wall_time, "%.1f") << " s; "
     << (violations == 0 ? "no invariant violated" : std::to_string(violations) + " INVARIANT VIOLATIONS") << "\n\n"
     << "worst error: relative (absolute where the reference is 0) of the worst check, among the failed ones "
        "when some failed. energy (Moreau–Jean only): `ok`, `creates energy X J` (a dissipation below "
     << number(-kCreatedEnergyTolerance, "%.0e") << " × scale) or `balance residual X J` (worst |residual| above "
     << number(kBalanceTolerance, "%.0e")
     << " × scale), scale = max(|W_loads|, E_kin + E_el, initial E_kin + E_el). steps: Moreau–Jean's time steps, "
        "IDA's internal steps. wall time: the time loop; for a stopped run, loading and running until it stopped.\n";
  std::vector<std::string> sweeps;
  for (const StabilityRow& row : study.rows)
    if (std::find(sweeps.begin(), sweeps.end(), row.sweep) == sweeps.end()) sweeps.push_back(row.sweep);
  for (const std::string& sweep : sweeps) {
    const auto first = std::find_if(study.rows.begin(), study.rows.end(),
                                    [&](const StabilityRow& r) { return r.sweep == sweep; });
    md << "\n## " << sweep << " (`" << first->key << "`)\n\n";
    write_markdown_table(md, study, sweep);
  }
  return md.str();
}

std::string stability_csv(const StabilityStudy& study) {
  std::ostringstream csv;
  csv << "# csim stress: stability study of scene " << study.scene_name << " (" << study.scene_file << ")\n"
      << "# sweeps: " << study.sweeps_file << "; baseline: " << (study.baseline.empty() ? "none" : join(study.baseline, " "))
      << "; overrides: " << (study.overrides.empty() ? "none" : join(study.overrides, " ")) << "\n"
      << "# placement: " << study.placement << "\n"
      << "# worst_error: relative (worst_error_kind rel) or absolute where the reference is 0 (abs), of worst_check; "
         "empty with a worst_check: not evaluated\n"
         "# energy (J, final state): judged for moreau-jean only; scale = max(|W_loads|, E_kin + E_el, initial sum)\n"
         "# steps: moreau-jean time steps, ida internal steps; wall_time (s): the time loop, or load + run until "
         "a stop\n";
  csv << "sweep,key,value,integrator,outcome,worst_error,worst_error_kind,worst_check,failed_checks,energy,"
         "contact_dissipation,numerical_dissipation,max_abs_residual,energy_scale,wall_time,steps,stopped_at,"
         "non_finite,invariant_violated,message\n";
  for (const StabilityRow& row : study.rows) {
    const bool ran = ran_to_the_end(row), stopped = row.outcome == StabilityOutcome::stopped;
    csv << csv_field(row.sweep) << ',' << csv_field(row.key) << ',' << csv_field(row.value) << ','
        << row.integrator << ',' << outcome_name(row.outcome) << ','
        << (row.worst_check.empty() ? "" : number(row.worst_error, "%.6e")) << ','
        << (row.worst_check.empty() ? "" : row.worst_error_relative ? "rel" : "abs") << ','
        << csv_field(row.worst_check) << ',' << csv_field(join(row.failed_checks, ";")) << ','
        << csv_field(row.energy_verdict()) << ',' << (ran ? number(row.contact_dissipation, "%.6e") : "") << ','
        << (ran ? number(row.numerical_dissipation, "%.6e") : "") << ','
        << (ran ? number(row.max_abs_residual, "%.6e") : "") << ',' << (ran ? number(row.energy_scale, "%.6e") : "")
        << ',' << number(row.wall_time, "%.6g") << ',' << (row.steps >= 0 ? std::to_string(row.steps) : "") << ','
        << (stopped ? number(row.stopped_at, "%.9g") : "") << ',' << csv_field(join(row.non_finite, ";")) << ','
        << (row.violates_invariant() ? "yes" : "no") << ',' << csv_field(row.message) << '\n';
  }
  return csv.str();
}

void write_stability_markdown(const StabilityStudy& study, const std::string& directory) {
  std::filesystem::create_directories(directory);
  write_file_atomically((std::filesystem::path(directory) / "stability.md").string(), stability_markdown(study));
}

void write_stability_csv(const StabilityStudy& study, const std::string& directory) {
  std::filesystem::create_directories(directory);
  write_file_atomically((std::filesystem::path(directory) / "stability.csv").string(), stability_csv(study));
}

}  // namespace csim
