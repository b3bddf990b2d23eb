// csim: the command-line program (docs/contract.md); its commands and options are read in command_line.cpp.
//   csim run SCENE [--set KEY=VALUE]... [--out DIR] [--quiet]
//   csim validate SCENE [--set KEY=VALUE]...
//   csim dump-config SCENE [--set KEY=VALUE]...
//   csim compare SCENE [--set KEY=VALUE]... --integrators LIST [--steps LIST] [--tolerances LIST]
//                [--repeats N] [--reference auto|analytical|ida-events|moreau-jean] [--out DIR]
//   csim stress SCENE [--set KEY=VALUE]... [--sweeps FILE] [--out DIR] [--only SWEEP[,SWEEP...]]
//   csim sweep SCENE [--set KEY=VALUE]... (--set-list KEY=V1,V2...|--grid KEY=V1,V2...)... | --sweeps FILE
//              [--out DIR] [--no-case-outputs]
//   csim solve PROBLEM [--tolerance T] [--max-iterations N] [--out FILE]   (solve_command.h)
//   csim help [COMMAND], csim [COMMAND] --help: help on stdout, exit 0; a bad argument: one line, exit 2.
// SCENE is a scene folder (holding scene.yaml) or a YAML file.
// run, compare, stress and sweep write into a temporary folder beside DIR and swap it in whole when they
// end (tools/output/output_folder.h); SIGINT, SIGTERM or SIGHUP stops them at the next step boundary or
// between runs, removes that folder and leaves DIR as it was: exit status 130, 143 or 129 (128 + the
// signal). A run stopped by a numerical failure (exit 2) leaves in DIR what it computed up to the failure,
// its summary.json saying "failed" (tools/run/run.h).
// Exit status of run: 0 checks passed (checks.h: CheckCounts::pass) or a scene without checks run to its
// end (RunReport::plain_simulation), 1 not a pass, 2 bad input, a numerical failure or an environment
// failure (a file that cannot be written, out of memory).
// Exit status of compare: 0 every run succeeded, 1 some run failed (recorded in its row), 2 bad input.
// Exit status of stress: 0 no run violated an invariant (failed checks and IDA stops are only reported),
// 1 some run did, 2 bad input (sweeps file, --only, --set).
// Exit status of sweep: 0 every case passed its checks, 1 some case did not (recorded in its row), 2 bad input.
// Exit status of solve: 0 converged, 1 not converged, 2 bad input or an output file that cannot be written.
// compare, stress and sweep run their cases through a study runner (tools/studies/study_runner.h): serially,
// or spread over the ranks when started by mpirun or srun, rank 0 alone printing and writing; the other
// ranks leave quietly, with status 0 once the study is done or 2 when it could not start. A stopped study
// ends every rank at once with 128 + the signal (StudyRunner::leave_at_once).
#include "tools/studies/compare.h"
#include "tools/output/atomic_file.h"
#include "tools/output/output_folder.h"
#include "tools/run/run.h"
#include "tools/scene/contact_pairs_listing.h"
#include "tools/scene/scene.h"
#include "engine/steppers/stepper.h"
#include "tools/run/stop_request.h"
#include "tools/studies/stability_sweep.h"
#include "tools/studies/mpi_study_runner.h"
#include "tools/studies/sweep.h"
#include "tools/command_line.h"
#include "tools/scene_argument.h"
#include "tools/solve_command.h"
#include "tools/stop_signals.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <new>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace {

constexpr int kPassed = 0, kCheckFailed = 1, kBadInput = csim::cli::kBadInput;
constexpr int kSomeRunFailed = 1;  // compare
constexpr int kInvariantViolated = 1;  // stress

using csim::cli::Arguments;

// Thrown on the ranks other than 0 when rank 0 could not start the study: rank 0 says why.
struct RankLeaves {};

// Rank 0 opens the output folder of a study and every rank learns its temporary path, where the cases
// write their own outputs. The path shared is empty when rank 0 failed: it throws its error, the others
// RankLeaves, so that no rank waits for a study that will not start.
std::string open_study_folder(csim::StudyRunner& runner, const std::string& destination,
                              std::optional<csim::OutputFolder>& folder) {
  std::string path;
  if (runner.is_root()) {
    try {
      folder.emplace(destination);
      path = folder->path();
    } catch (...) {
      runner.share("");
      throw;
    }
  }
  path = runner.share(path);
  if (path.empty()) throw RankLeaves{};
  return path;
}

// The output folder of a command: --out, or out/<scene name><suffix>.
std::string output_destination(const Arguments& arguments, const std::string& file, const std::string& suffix) {
  if (!arguments.output_directory.empty()) return arguments.output_directory;
  return "out/" + csim::load_scene(file, arguments.overrides)->name + suffix;
}

// Runs `write`, which writes into the temporary folder of `folder`: a file it cannot write is named in
// `destination`, the folder the user asked for, since the temporary one is gone when the command fails.
template <typename Write>
void writing_into(const csim::OutputFolder& folder, const std::string& destination, Write&& write) {
  try {
    write();
  } catch (const csim::FileWriteError& e) {
    throw e.in_folder(folder.path(), destination);
  }
}

// Runs the scene into a temporary folder that replaces options.output_directory when the run ends: passed,
// failed its checks, or stopped by a numerical failure. The last leaves what it computed up to the failure
// with a summary.json saying "failed" (run.h), and the folder is swapped in all the same: an earlier run's
// results must not pass for this one's. A stop request leaves the folder as it was.
csim::RunReport run_into_folder(const csim::Scene& scene, const csim::RunOptions& options) {
  csim::check_outputs(scene);  // the scene's mistakes before any file is touched
  csim::OutputFolder folder(options.output_directory);
  csim::RunOptions into_temporary = options;
  into_temporary.output_directory = folder.path();
  try {
    csim::RunReport report;
    writing_into(folder, options.output_directory, [&] { report = csim::run_scene(scene, into_temporary); });
    csim::honour_stop_request();
    folder.commit();
    return report;
  } catch (const csim::RunError&) {
    folder.commit();
    throw;
  }
}

void print_checks(const std::vector<csim::CheckResult>& checks) {
  for (const csim::CheckResult& c : checks) {
    if (c.skipped) {
      std::printf("  SKIP  %-22s %s\n", c.name.c_str(), c.note.c_str());
      continue;
    }
    if (!c.note.empty()) {
      std::printf("  %s  %-22s %s\n", c.evaluated ? "FAIL" : "N/A ", c.name.c_str(), c.note.c_str());
      continue;
    }
    const double relative = c.reference != 0.0 ? std::abs(c.error / c.reference) : std::abs(c.error);
    std::printf("  %s  %-22s %-8s value %-14.8g reference %-14.8g error %.2e (%s %.2e, tol abs %.1e rel %.1e) [%s]\n",
                c.passed ? "PASS" : "FAIL", c.name.c_str(), c.probe.c_str(), c.value, c.reference,
                c.error, c.reference != 0.0 ? "rel" : "abs", relative, c.absolute_tolerance,
                c.relative_tolerance, c.kind.c_str());
  }
}

// One line: the verdict and the counts behind it (checks.h: CheckCounts::pass).
std::string verdict(const csim::CheckCounts& n) {
  const std::string counts = std::to_string(n.passed) + " passed, " + std::to_string(n.failed) + " failed, " +
                             std::to_string(n.not_evaluated) + " not evaluated, " + std::to_string(n.excluded) +
                             " excluded by only_if";
  if (n.pass()) return "checks passed (" + counts + ")";
  if (n.failed > 0) return "CHECKS FAILED (" + counts + ")";
  if (n.total() == 0) return "no checks: a plain simulation, run to its end";
  if (n.not_evaluated > 0) return "NOT JUDGED: some checks could not be evaluated (not a pass; " + counts + ")";
  return "NOT JUDGED: no check applies to these parameters (not a pass; " + counts + ")";
}

void print_summary(const csim::Scene& scene, const csim::RunReport& report) {
  const csim::SolverCounters& c = report.state.counters;
  const csim::IdaStatistics& ida = report.state.ida;
  if (csim::is_ida(scene.run.integrator)) {
    std::printf("%s: IDA (rtol %g, atol %g, %s) to t = %g s in %.3f s: %ld steps, %ld residual evaluations, "
                "%ld Jacobians, %ld error-test and %ld convergence failures\n",
                scene.name.c_str(), scene.run.ida.rtol, scene.run.ida.atol, ida.linear_solver.c_str(),
                report.state.t, report.wall_time, ida.steps, ida.residual_evaluations, ida.jacobian_evaluations,
                ida.error_test_failures, ida.nonlinear_convergence_failures);
    if (ida.linear_solver == "klu")
      std::printf("  KLU: %ld symbolic analyses of the Jacobian's pattern\n", ida.symbolic_analyses);
  } else {
    std::printf("%s: %ld steps of %g s in %.3f s (%.3g steps/s)\n", scene.name.c_str(), c.steps,
                scene.run.step, report.wall_time, report.wall_time > 0 ? c.steps / report.wall_time : 0.0);
  }
  if (c.solves > 0)
    std::printf("  contact solver: %ld solves, %.2f sweeps on average, %d at most, max residual %.1e\n",
                c.solves, double(c.total_iterations) / c.solves, c.max_iterations, c.max_residual);
  if (c.not_converged > 0)
    std::printf("  warning: the contact solver stayed above its tolerance in %ld of %ld solves (first at t = %g s)\n",
                c.not_converged, c.solves, c.first_not_converged_time);
  if (scene.run.integrator == csim::Integrator::quasi_static || c.newton_iterations > 0)
    std::printf("  Newton: %ld iterations, %.2f a step on average, %d at most, %ld regularized, %ld held by contacts\n",
                c.newton_iterations, c.steps > 0 ? double(c.newton_iterations) / c.steps : 0.0, c.max_newton_iterations,
                c.newton_regularized, c.newton_held);
  const csim::PhaseTimers& t = report.state.timers;
  if (t.free_velocity + t.detection + t.assembly + t.solve + t.update > 0.0)
    std::printf("  phases (summary.json timers): %s %.3g s, detection %.3g s, assembly %.3g s, contact solve %.3g s, "
                "update %.3g s\n",
                scene.run.integrator == csim::Integrator::quasi_static ? "forces, tangent and its factorization" : "free velocity",
                t.free_velocity, t.detection, t.assembly, t.solve, t.update);
  if (c.cutbacks > 0)
    std::printf("  note: %ld load steps were taken again as two halves after Newton failed (integrator.max_cutbacks)\n",
                c.cutbacks);
  const csim::EnergyBalance& e = report.state.energy;
  if (!report.energy_balance_tracked) {  // no inertia: the balance of work is not tracked
    std::printf("  energy: elastic %.6g J (the quasi-static stepper keeps no balance of work)\n", e.elastic);
    return;
  }
  // generalized-alpha keeps no independent balance: its numerical dissipation is what closes it.
  const bool closing = scene.run.integrator == csim::Integrator::generalized_alpha;
  std::printf("  energy: kinetic %.6g J, elastic %.6g J, work of loads %.6g J, contact dissipation %.6g J, "
              "numerical dissipation%s %.3g J, ",
              e.kinetic, e.elastic, e.work_of_loads, e.contact_dissipation,
              closing ? " (what closes the balance)" : "", e.numerical_dissipation);
  if (e.damping_dissipation != 0.0) std::printf("damping dissipation %.6g J, ", e.damping_dissipation);
  if (e.sleep_dissipation != 0.0) std::printf("put to sleep %.3g J, ", e.sleep_dissipation);
  if (closing) std::printf("no independent balance\n");
  else std::printf("balance residual %.2e J\n", e.residual());
}

void print_compare_header() {
  std::printf("%-11s %-15s %-9s %15s %9s %13s  %s\n", "integrator", "parameter", "value", "median wall (s)",
              "steps", "max rel error", "status");
}

void print_compare_row(const csim::CompareRow& row) {
  std::string status = row.ok ? "ok" : "failed: " + row.failure;
  if (row.ok && !row.not_evaluated.empty()) {
    status += ", could not evaluate";
    for (const std::string& name : row.not_evaluated) status += " " + name;
  }
  char wall[32] = "-", error[32] = "-";
  if (std::isfinite(row.wall_time_median)) std::snprintf(wall, sizeof wall, "%.4g", row.wall_time_median);
  if (std::isfinite(row.max_rel_error)) std::snprintf(error, sizeof error, "%.3e", row.max_rel_error);
  std::printf("%-11s %-15s %-9g %15s %9s %13s  %s\n", row.integrator.c_str(), row.parameter.c_str(), row.value,
              wall, row.ok ? std::to_string(row.steps).c_str() : "-", error, status.c_str());
  std::fflush(stdout);  // the table is the progress report of a long study
}

int run_compare(const Arguments& arguments, const std::string& file, csim::StudyRunner& runner) {
  csim::CompareOptions options;
  options.scene_file = file;
  options.overrides = arguments.overrides;
  options.integrators = arguments.integrators;
  options.steps = arguments.steps;
  options.tolerances = arguments.tolerances;
  options.repeats = arguments.repeats;
  options.reference = arguments.reference;
  options.output_directory = output_destination(arguments, file, "-compare");
  std::optional<csim::OutputFolder> folder;
  open_study_folder(runner, options.output_directory, folder);
  bool header_printed = false;  // not before the options and the scene are known to be good
  const csim::Comparison comparison = csim::run_comparison(options, [&](const csim::CompareRow& row) {
    if (!header_printed) print_compare_header();
    header_printed = true;
    print_compare_row(row);
  }, runner);
  if (!runner.is_root()) return kPassed;
  const std::string& directory = options.output_directory;
  writing_into(*folder, directory, [&] {
    csim::write_work_precision_csv(comparison, folder->path());
    csim::write_gnuplot_script(comparison, folder->path());
  });
  const csim::PlotOutcome plot = csim::plot_work_precision(comparison, folder->path());
  if (!plot.produced) std::cerr << "csim: warning: no work_precision.png: " << plot.message << "\n";
  csim::honour_stop_request();
  folder->commit();
  const auto failed = std::count_if(comparison.rows.begin(), comparison.rows.end(),
                                    [](const csim::CompareRow& r) { return !r.ok; });
  std::printf("%s: %zu configurations, %s (outputs in %s)\n", comparison.scene_name.c_str(), comparison.rows.size(),
              failed == 0 ? "all runs succeeded" : (std::to_string(failed) + " FAILED").c_str(), directory.c_str());
  return comparison.all_ok() ? kPassed : kSomeRunFailed;
}

void print_stress_header() {
  std::printf("%-34s %-11s %-12s %-32s %-26s %9s %9s  %s\n", "case", "integrator", "outcome", "worst error", "energy",
              "wall (s)", "steps", "note");
}

void print_stress_row(const csim::StabilityRow& row) {
  char wall[32];
  std::snprintf(wall, sizeof wall, "%.3g", row.wall_time);
  std::printf("%-34s %-11s %-12s %-32s %-26s %9s %9s  %s\n", row.case_name().c_str(), row.integrator.c_str(),
              csim::outcome_name(row.outcome), row.worst_error_text().c_str(), row.energy_verdict().c_str(), wall,
              row.steps >= 0 ? std::to_string(row.steps).c_str() : "-", row.note().c_str());
  std::fflush(stdout);  // the table is the progress report of a long study
}

int run_stability_command(const Arguments& arguments, const std::string& file, csim::StudyRunner& runner) {
  csim::StabilityOptions options;
  options.scene_file = file;
  options.sweeps_file = arguments.sweeps_file;
  options.overrides = arguments.overrides;
  options.only = arguments.only;
  const std::string directory = output_destination(arguments, file, "-stress");
  std::optional<csim::OutputFolder> folder;
  open_study_folder(runner, directory, folder);
  bool header_printed = false;  // not before the sweeps file and the scene are known to be good
  const csim::StabilityStudy study = csim::run_stability_sweep(options, [&](const csim::StabilityRow& row) {
    if (!header_printed) print_stress_header();
    header_printed = true;
    print_stress_row(row);
  }, runner);
  if (!runner.is_root()) return kPassed;
  writing_into(*folder, directory, [&] {
    csim::write_stability_markdown(study, folder->path());
    csim::write_stability_csv(study, folder->path());
  });
  csim::honour_stop_request();
  folder->commit();
  const auto violations = std::count_if(study.rows.begin(), study.rows.end(),
                                        [](const csim::StabilityRow& r) { return r.violates_invariant(); });
  std::printf("%s: %zu runs in %.1f s, %s (outputs in %s)\n", study.scene_name.c_str(), study.rows.size(),
              study.total_wall_time,
              violations == 0 ? "no invariant violated" : (std::to_string(violations) + " INVARIANT VIOLATIONS").c_str(),
              directory.c_str());
  return violations == 0 ? kPassed : kInvariantViolated;
}

void print_sweep_row(std::size_t index, const csim::SweepRow& row) {
  std::string settings;
  for (const std::string& s : row.settings) settings += (settings.empty() ? "" : " ") + s;
  char wall[32];
  std::snprintf(wall, sizeof wall, "%.3g", row.wall_time);
  std::printf("%5zu  %-50s %-17s %9s %9s  %s\n", index + 1, settings.c_str(), row.status.c_str(),
              row.steps >= 0 ? std::to_string(row.steps).c_str() : "-", wall, row.message.c_str());
  std::fflush(stdout);  // the table is the progress report of a long study
}

int run_sweep_command(const Arguments& arguments, const std::string& file, csim::StudyRunner& runner) {
  csim::SweepOptions options;
  options.scene_file = file;
  options.overrides = arguments.overrides;
  options.set_lists = arguments.set_lists;
  options.grids = arguments.grids;
  options.sweeps_file = arguments.sweeps_file;
  const std::string directory = output_destination(arguments, file, "-sweep");
  std::optional<csim::OutputFolder> folder;
  const std::string path = open_study_folder(runner, directory, folder);
  if (!arguments.no_case_outputs) options.case_directory = path;
  options.shown_directory = directory;
  std::size_t printed = 0;  // the header not before the cases are known to be good
  const csim::SweepStudy study = csim::run_sweep(options, [&](const csim::SweepRow& row) {
    if (printed == 0)
      std::printf("%5s  %-50s %-17s %9s %9s  %s\n", "case", "settings", "status", "steps", "wall (s)", "message");
    print_sweep_row(printed++, row);
  }, runner);
  if (!runner.is_root()) return kPassed;
  writing_into(*folder, directory, [&] { csim::write_sweep_csv(study, folder->path()); });
  csim::honour_stop_request();
  folder->commit();
  const auto not_passed = std::count_if(study.rows.begin(), study.rows.end(),
                                        [](const csim::SweepRow& r) { return r.exit_status != 0; });
  std::printf("%s: %zu cases in %.1f s, %s (%s; outputs in %s)\n", study.scene_name.c_str(), study.rows.size(),
              study.total_wall_time,
              not_passed == 0 ? "all passed" : (std::to_string(not_passed) + " NOT PASSED").c_str(),
              study.placement.c_str(), directory.c_str());
  return not_passed == 0 ? kPassed : kSomeRunFailed;
}

// The line that reports a numerical failure of the scene in `file`.
std::string numerical_failure(const std::string& file, const csim::RunError& e) {
  std::ostringstream line;
  line << "csim: " << file << ": numerical failure at t = " << e.time << " s: " << e.what();
  return line.str();
}

// The command, once its arguments are read and its runner is chosen; returns its exit status, and sets
// `stopped` when a stop request ended it (stop_request.h).
int run_command(const Arguments& arguments, csim::StudyRunner& runner, bool& stopped) {
  std::string file = arguments.scene;
  const bool speaks = runner.is_root();  // rank 0, or the only process: the one that prints errors
  try {
    file = csim::cli::scene_file(arguments.scene);
    if (arguments.command == "compare") return run_compare(arguments, file, runner);
    if (arguments.command == "stress") return run_stability_command(arguments, file, runner);
    if (arguments.command == "sweep") return run_sweep_command(arguments, file, runner);
    const auto scene = csim::load_scene(file, arguments.overrides);
    if (arguments.command == "validate") {
      csim::make_stepper(scene->world, scene->run);  // what the stepper refuses at its construction, as run would
      csim::check_outputs(*scene);  // what the output writers would refuse, as run does before its first step
      std::printf("%s: valid (%zu bodies, %zu probes, %zu checks)\n", file.c_str(), scene->world.bodies.size(),
                  scene->run.probes.size(), scene->run.checks.size());
      std::fputs(csim::contact_pairs_listing(scene->world).c_str(), stdout);
      return kPassed;
    }
    if (arguments.command == "dump-config") {
      std::cout << csim::dump_config(*scene);
      return kPassed;
    }
    csim::RunOptions options;
    options.output_directory =
        arguments.output_directory.empty() ? "out/" + scene->name : arguments.output_directory;
    options.progress = !arguments.quiet && isatty(fileno(stderr));
    std::optional<csim::RunReport> finished;
    try {
      finished = run_into_folder(*scene, options);
    } catch (const csim::RunError& e) {
      std::cerr << numerical_failure(file, e)
                << "\ncsim: the outputs up to the failure are in " << options.output_directory
                << " (summary.json: \"status\": \"failed\")\n";
      return kBadInput;
    }
    const csim::RunReport& report = *finished;
    if (!arguments.quiet) print_summary(*scene, report);
    print_checks(report.checks);
    std::printf("%s: %s (outputs in %s)\n", scene->name.c_str(), verdict(report.counts()).c_str(),
                options.output_directory.c_str());
    return report.passed() || report.plain_simulation() ? kPassed : kCheckFailed;
  } catch (const RankLeaves&) {
  } catch (const csim::StopRequested& stop) {
    stopped = true;
    if (speaks)
      std::cerr << "csim: stopped by " << csim::cli::signal_name(stop.signal)
                << " before the end; the output folder is left as it was\n";
    return 128 + stop.signal;
  } catch (const csim::SceneError& e) {
    if (speaks) std::cerr << "csim: error: " << e.what() << "\n";
  } catch (const csim::OutputFolderError& e) {
    if (speaks) std::cerr << "csim: " << e.what() << "\n";
  } catch (const csim::RunError& e) {
    if (speaks) std::cerr << numerical_failure(file, e) << "\n";
  } catch (const std::bad_alloc&) {  // an environment failure (docs/contract.md): exit 2, the message says which
    if (speaks) std::cerr << "csim: " << file << ": out of memory (the system refused an allocation)\n";
  } catch (const std::system_error& e) {  // a file that cannot be written (atomic_file.h), named in --out
    if (speaks) std::cerr << "csim: " << e.what() << "\n";
  } catch (const std::exception& e) {
    if (speaks) std::cerr << "csim: " << file << ": " << e.what() << "\n";
  }
  return kBadInput;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments arguments;
  if (const std::optional<int> status = csim::cli::parse_command_line(argc, argv, arguments)) return *status;
  if (arguments.command == "solve") return csim::cli::solve_command(arguments.solve);
  const bool study = arguments.command == "compare" || arguments.command == "stress" || arguments.command == "sweep";
  if (arguments.command == "run" || study) csim::cli::install_stop_handlers();
  // Lives as long as the command: MPI is finalized when main returns (mpi_study_runner.h).
  std::unique_ptr<csim::StudyRunner> mpi_runner;
  try {
    if (study) mpi_runner = csim::make_mpi_runner(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "csim: " << e.what() << "\n";
    return kBadInput;
  }
  csim::StudyRunner& runner = mpi_runner ? *mpi_runner : csim::serial_runner();
  bool stopped = false;
  const int status = run_command(arguments, runner, stopped);
  // A stopped study (every rank learns it from rank 0), or a rank that a signal reached, leaves at once,
  // its outputs cleaned up: MPI_Finalize waits for the launcher, which is taking the job down (OpenMPI's
  // mpirun kept such a rank 1-2 s, then killed it or let it go; a launcher that does not answer, for ever).
  if (mpi_runner && (stopped || csim::stop_request() != 0)) mpi_runner->leave_at_once(status);
  return status;
}
