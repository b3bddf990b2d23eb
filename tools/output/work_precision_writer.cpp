// The outputs of `csim compare`: work_precision.csv, work_precision.gp and the PNG gnuplot draws from it.
#include "tools/output/work_precision_writer.h"
#include "tools/output/csv_text.h"
#include "tools/output/atomic_file.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace csim {

namespace {

std::string number(double x, int digits = 10) {
  if (!std::isfinite(x)) return "";  // an empty cell: not measured
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, x);
  return buffer;
}

void write_comment_header(std::ostringstream& csv, const Comparison& comparison) {
  csv << "# csim compare: work-precision study of scene " << comparison.scene_name << " ("
      << comparison.scene_file << ")\n";
  if (!comparison.description.empty()) csv << "# description: " << one_line(comparison.description) << "\n";
  csv << "# overrides:";
  if (comparison.overrides.empty()) csv << " none";
  for (const std::string& o : comparison.overrides) csv << " --set " << o;
  csv << "\n# placement: " << comparison.placement << " (the wall times are only comparable with one run per core)";
  csv << "\n# each run also gets integrator.type=INTEGRATOR, then time.step=VALUE (moreau-jean, generalized-alpha) or "
         "integrator.rtol=integrator.atol=VALUE (ida, ida-events; time.step stays the probes' sampling interval)\n"
         "# wall times: s, of the time loop, one per repeat (';'-separated); wall_time_median is their median\n"
         "# steps: moreau-jean, generalized-alpha: time steps; ida, ida-events: IDA's internal steps\n"
         "# solver_iterations: moreau-jean, generalized-alpha: projected Gauss-Seidel sweeps summed over the run; ida, ida-events: "
         "IDA's residual evaluations\n"
         "# C_error = |value - reference|, C_rel_error = C_error / |reference| (empty when the reference is 0, the run "
         "failed or could not evaluate C); max_rel_error = largest C_rel_error over the analytical checks "
         "(those a run could not evaluate are named in its status)\n"
         "# reference: " << comparison.reference << "\n";
  if (comparison.trajectory_reference)
    csv << "# max_rel_error: largest over the displacement and position probes of max_t |p(t) - p_ref(t)| / max_t |p_ref(t)| at the rows of "
           "probes.csv (the reference interpolated linearly); the check columns are the scene's own checks\n";
  for (const ComparedCheck& c : comparison.checks) {
    csv << "# check " << c.name << ": kind " << c.kind << ", reference " << one_line(c.reference);
    if (c.reference_known && number(c.reference_value) != one_line(c.reference))
      csv << " = " << number(c.reference_value, 12);
    csv << ", source: " << one_line(c.source) << "\n";
  }
}

std::string status_text(const CompareRow& row) {
  if (!row.ok) return "failed: " + row.failure;
  std::string status = "ok";
  if (!row.not_evaluated.empty()) {
    status += "; not evaluated:";
    for (const std::string& name : row.not_evaluated) status += " " + name;
  }
  return status;
}

std::string csv_row(const CompareRow& row) {
  std::ostringstream line;
  line << csv_field(row.integrator) << ',' << row.parameter << ',' << number(row.value) << ','
       << number(row.wall_time_median, 6) << ',';
  for (std::size_t k = 0; k < row.wall_times.size(); ++k) line << (k ? ";" : "") << number(row.wall_times[k], 6);
  line << ',' << (row.ok ? std::to_string(row.steps) : "") << ','
       << (row.ok ? std::to_string(row.solver_iterations) : "") << ','
       << csv_field(status_text(row)) << ',' << number(row.max_rel_error);
  for (std::size_t k = 0; k < row.errors.size(); ++k)
    line << ',' << number(row.errors[k]) << ',' << number(row.relative_errors[k]);
  return line.str();
}

// A point can go on log-log axes only when both coordinates are positive and finite.
bool plottable(const CompareRow& row) {
  return row.ok && row.max_rel_error > 0.0 && std::isfinite(row.max_rel_error) && row.wall_time_median > 0.0 &&
         std::isfinite(row.wall_time_median);
}

std::string datablock_name(const std::string& integrator) {
  std::string name = "$";
  for (char c : integrator) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return name;
}

std::string point_label(const CompareRow& row) {
  return (row.parameter == "time.step" ? "h=" : "tol=") + number(row.value, 6);
}

// gnuplot cannot autoscale an axis on which every point has the same coordinate (a single run, say):
// such an axis gets a range of a decade around that value.
void write_degenerate_ranges(std::ostringstream& gp, const Comparison& comparison) {
  double x_min = INFINITY, x_max = 0.0, y_min = INFINITY, y_max = 0.0;
  for (const CompareRow& row : comparison.rows) {
    if (!plottable(row)) continue;
    x_min = std::min(x_min, row.wall_time_median);
    x_max = std::max(x_max, row.wall_time_median);
    y_min = std::min(y_min, row.max_rel_error);
    y_max = std::max(y_max, row.max_rel_error);
  }
  if (x_min == x_max) gp << "set xrange [" << number(x_min / 3.0) << ":" << number(x_max * 3.0) << "]\n";
  if (y_min == y_max) gp << "set yrange [" << number(y_min / 3.0) << ":" << number(y_max * 3.0) << "]\n";
}

}  // namespace

std::string work_precision_csv(const Comparison& comparison) {
  std::ostringstream csv;
  write_comment_header(csv, comparison);
  csv << "integrator,parameter,value,wall_time_median,wall_times,steps,solver_iterations,status,max_rel_error";
  for (const ComparedCheck& c : comparison.checks) csv << ',' << c.name << "_error," << c.name << "_rel_error";
  csv << '\n';
  for (const CompareRow& row : comparison.rows) csv << csv_row(row) << '\n';
  return csv.str();
}

void write_work_precision_csv(const Comparison& comparison, const std::string& directory) {
  std::filesystem::create_directories(directory);
  write_file_atomically((std::filesystem::path(directory) / "work_precision.csv").string(),
                        work_precision_csv(comparison));
}

std::string gnuplot_script(const Comparison& comparison) {
  std::ostringstream gp;
  gp << "# Work-precision diagram of scene " << comparison.scene_name << ", written by csim compare.\n"
        "# Run `gnuplot work_precision.gp` in this folder. The data are the rows of work_precision.csv that\n"
        "# succeeded with a non-zero max_rel_error (log axes): median wall time (s), max_rel_error, label.\n";
  std::vector<std::string> integrators;  // those with at least one point, in the order of the study
  for (const CompareRow& row : comparison.rows) {
    if (!plottable(row)) continue;
    if (std::find(integrators.begin(), integrators.end(), row.integrator) == integrators.end())
      integrators.push_back(row.integrator);
  }
  for (const std::string& integrator : integrators) {
    gp << datablock_name(integrator) << " << EOD\n";
    for (const CompareRow& row : comparison.rows)
      if (row.integrator == integrator && plottable(row))
        gp << number(row.wall_time_median, 8) << ' ' << number(row.max_rel_error, 8) << " \"" << point_label(row)
           << "\"\n";
    gp << "EOD\n";
  }
  gp << "if (strstrt(GPVAL_TERMINALS, \"pngcairo\") > 0) {\n"
        "  set terminal pngcairo size 1000,700 font \",11\"\n"
        "} else {\n"
        "  set terminal png size 1000,700\n"
        "}\n"
        "set output \"work_precision.png\"\n"
        "set title \"" << comparison.scene_name << ": work-precision (max relative error of the analytical checks)\"\n"
        "set xlabel \"median wall time of the time loop (s)\"\n"
        "set ylabel \"max relative error\"\n"
        "set logscale xy\n"
        "set format x \"%g\"\n"
        "set format y \"%.0e\"\n"
        "set grid\n"
        "set key top right\n"
        "set offsets graph 0.05, graph 0.15, graph 0.1, graph 0.1\n";
  if (integrators.empty()) return gp.str() + "# nothing to plot: no run succeeded with a non-zero error\n";
  write_degenerate_ranges(gp, comparison);
  gp << "plot ";
  for (std::size_t k = 0; k < integrators.size(); ++k) {
    const std::string block = datablock_name(integrators[k]);
    gp << (k ? ", \\\n     " : "") << block << " using 1:2 with linespoints linecolor " << k + 1
       << " pointtype 7 title \"" << integrators[k] << "\", \\\n     " << block
       << " using 1:2:3 with labels offset char 1,0.6 left textcolor lt " << k + 1 << " notitle";
  }
  gp << "\n";
  return gp.str();
}

void write_gnuplot_script(const Comparison& comparison, const std::string& directory) {
  std::filesystem::create_directories(directory);
  write_file_atomically((std::filesystem::path(directory) / "work_precision.gp").string(),
                        gnuplot_script(comparison));
}

PlotOutcome plot_work_precision(const Comparison& comparison, const std::string& directory) {
  if (std::none_of(comparison.rows.begin(), comparison.rows.end(), plottable))
    return {false, "no run succeeded with a non-zero error: nothing to plot"};
  const std::filesystem::path png = std::filesystem::path(directory) / "work_precision.png";
  std::error_code ignored;
  std::filesystem::remove(png, ignored);  // no stale plot of an earlier study
  const pid_t child = fork();
  if (child < 0) return {false, "cannot start gnuplot (fork failed)"};
  if (child == 0) {
    if (chdir(directory.c_str()) != 0) _exit(126);
    execlp("gnuplot", "gnuplot", "work_precision.gp", static_cast<char*>(nullptr));
    _exit(127);  // exec failed: gnuplot is not installed (or not on PATH)
  }
  int status = 0;
  if (waitpid(child, &status, 0) < 0) return {false, "lost track of gnuplot (waitpid failed)"};
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (code == 127)
    return {false, "gnuplot not found (Debian package gnuplot-nox); work_precision.gp is written, the plot is not"};
  if (code != 0 || !std::filesystem::exists(png)) {
    std::filesystem::remove(png, ignored);  // a half-drawn plot is no plot
    return {false, "gnuplot failed on work_precision.gp (exit status " + std::to_string(code) + ")"};
  }
  return {true, ""};
}

}  // namespace csim
