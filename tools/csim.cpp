// csim: the command-line program (DESIGN.md §4).
//   csim run SCENE [--set KEY=VALUE]... [--out DIR] [--quiet]
//   csim validate SCENE [--set KEY=VALUE]...
//   csim dump-config SCENE [--set KEY=VALUE]...
//   csim compare SCENE [--set KEY=VALUE]... --integrators LIST [--steps LIST] [--tolerances LIST]
//                [--repeats N] [--reference auto|analytical|ida-events|moreau-jean] [--out DIR]
//   csim stress SCENE [--set KEY=VALUE]... [--sweeps FILE] [--out DIR] [--only SWEEP[,SWEEP...]]
// SCENE is a scene folder (holding scene.yaml) or a YAML file.
// Exit status of run: 0 all checks pass, 1 a check fails, 2 bad input or a numerical failure.
// Exit status of compare: 0 every run succeeded, 1 some run failed (recorded in its row), 2 bad input.
// Exit status of stress: 0 no run violated an invariant (failed checks and IDA stops are only reported),
// 1 some run did, 2 bad input (sweeps file, --only, --set).
#include "engine/compare.h"
#include "engine/run.h"
#include "engine/scene/scene.h"
#include "engine/steppers/stepper.h"
#include "engine/stress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace {

constexpr int kPassed = 0, kCheckFailed = 1, kBadInput = 2;
constexpr int kSomeRunFailed = 1;  // compare
constexpr int kInvariantViolated = 1;  // stress

struct Arguments {
  std::string command, scene;
  std::vector<std::string> overrides;
  std::string output_directory;
  bool quiet = false;
  // compare
  std::vector<std::string> integrators;
  std::vector<double> steps, tolerances;
  int repeats = 3;
  std::string reference = "auto";
  // stress
  std::string sweeps_file;
  std::vector<std::string> only;
};

void usage(std::ostream& out) {
  out << "usage: csim run SCENE [--set KEY=VALUE]... [--out DIR] [--quiet]\n"
         "       csim validate SCENE [--set KEY=VALUE]...\n"
         "       csim dump-config SCENE [--set KEY=VALUE]...\n"
         "       csim compare SCENE [--set KEY=VALUE]... --integrators moreau-jean,ida[,ida-events]\n"
         "                    [--steps H1,H2,...] [--tolerances TOL1,TOL2,...] [--repeats N] [--out DIR]\n"
         "                    [--reference auto|analytical|ida-events|moreau-jean]\n"
         "       csim stress SCENE [--set KEY=VALUE]... [--sweeps FILE] [--out DIR] [--only SWEEP[,SWEEP...]]\n"
         "SCENE is a scene folder (with scene.yaml) or a scene file.\n"
         "compare runs moreau-jean once per step and ida, ida-events once per tolerance (rtol = atol), each N\n"
         "times (default 3), and writes DIR/work_precision.csv and .png (default DIR: out/<scene>-compare).\n"
         "stress runs each case of the sweeps FILE (default: stress.yaml beside the scene) with each of its\n"
         "integrators and writes DIR/stability.md and .csv (default DIR: out/<scene>-stress).\n"
         "Exit status: 0 checks pass (compare: every run succeeded; stress: no invariant violated), 1 a check\n"
         "fails (compare: a run failed; stress: an invariant was violated), 2 bad input or numerical failure.\n";
}

// "a,b,c" -> {a, b, c}; an empty item is an error.
bool split_list(const std::string& text, const std::string& option, std::vector<std::string>& items,
                std::string& error) {
  items.clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    items.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (items.back().empty()) { error = option + ": empty item in '" + text + "'"; return false; }
    if (comma == std::string::npos) return true;
    start = comma + 1;
  }
}

bool parse_numbers(const std::string& text, const std::string& option, std::vector<double>& numbers,
                   std::string& error) {
  std::vector<std::string> items;
  if (!split_list(text, option, items, error)) return false;
  numbers.clear();
  for (const std::string& item : items) {
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    if (end != item.c_str() + item.size() || !std::isfinite(x) || x <= 0.0) {
      error = option + ": '" + item + "' is not a positive number";
      return false;
    }
    numbers.push_back(x);
  }
  return true;
}

bool parse_repeats(const std::string& text, int& repeats, std::string& error) {
  char* end = nullptr;
  const long n = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || n < 1 || n > 1000000) {
    error = "--repeats: '" + text + "' is not a whole number >= 1";
    return false;
  }
  repeats = static_cast<int>(n);
  return true;
}

// The options of `compare` (its value already taken by next()); false with error set on bad input.
bool parse_compare_option(const std::string& option, const char* value, Arguments& a, std::string& error) {
  if (option == "--integrators") return split_list(value, option, a.integrators, error);
  if (option == "--steps") return parse_numbers(value, option, a.steps, error);
  if (option == "--tolerances") return parse_numbers(value, option, a.tolerances, error);
  if (option == "--reference") {
    a.reference = value;
    return true;
  }
  return parse_repeats(value, a.repeats, error);
}

bool is_compare_option(const std::string& arg) {
  return arg == "--integrators" || arg == "--steps" || arg == "--tolerances" || arg == "--repeats" ||
         arg == "--reference";
}

// The options of `stress` (its value already taken by next()).
bool parse_stress_option(const std::string& option, const char* value, Arguments& a, std::string& error) {
  if (option == "--only") return split_list(value, option, a.only, error);
  a.sweeps_file = value;
  return true;
}

bool is_stress_option(const std::string& arg) { return arg == "--sweeps" || arg == "--only"; }

bool is_command(const std::string& command) {
  return command == "run" || command == "validate" || command == "dump-config" || command == "compare" ||
         command == "stress";
}

bool writes_outputs(const std::string& command) {
  return command == "run" || command == "compare" || command == "stress";
}

bool parse(int argc, char** argv, Arguments& a, std::string& error) {
  if (argc < 3) { error = "missing command or scene"; return false; }
  a.command = argv[1];
  if (!is_command(a.command)) {
    error = "unknown command '" + a.command + "'";
    return false;
  }
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next = [&](const char* option) -> const char* {
      if (i + 1 >= argc) { error = std::string(option) + " needs a value"; return nullptr; }
      return argv[++i];
    };
    if (arg == "--set") {
      const char* value = next("--set");
      if (!value) return false;
      a.overrides.push_back(value);
    } else if (arg.rfind("--set=", 0) == 0) {
      a.overrides.push_back(arg.substr(6));
    } else if (arg == "--out" && writes_outputs(a.command)) {
      const char* value = next("--out");
      if (!value) return false;
      a.output_directory = value;
    } else if (arg == "--quiet" && a.command == "run") {
      a.quiet = true;
    } else if (is_compare_option(arg) && a.command == "compare") {
      const char* value = next(arg.c_str());
      if (!value || !parse_compare_option(arg, value, a, error)) return false;
    } else if (is_stress_option(arg) && a.command == "stress") {
      const char* value = next(arg.c_str());
      if (!value || !parse_stress_option(arg, value, a, error)) return false;
    } else if (!arg.empty() && arg[0] == '-') {
      error = "unknown option '" + arg + "'";
      return false;
    } else if (a.scene.empty()) {
      a.scene = arg;
    } else {
      error = "more than one scene given ('" + a.scene + "', '" + arg + "')";
      return false;
    }
  }
  if (a.scene.empty()) { error = "missing scene"; return false; }
  return true;
}

std::string scene_file(const std::string& scene) {
  if (std::filesystem::is_directory(scene)) return (std::filesystem::path(scene) / "scene.yaml").string();
  return scene;
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
  if (n.total() == 0) return "NOT JUDGED: the scene has no checks (not a pass)";
  if (n.not_evaluated > 0) return "NOT JUDGED: some checks could not be evaluated (not a pass; " + counts + ")";
  return "NOT JUDGED: no check applies to these parameters (not a pass; " + counts + ")";
}

void print_summary(const csim::Scene& scene, const csim::RunReport& report) {
  const csim::SolverCounters& c = report.state.counters;
  const csim::IdaStatistics& ida = report.state.ida;
  if (scene.run.integrator == "ida" || scene.run.integrator == "ida-events") {
    std::printf("%s: IDA (rtol %g, atol %g, %s) to t = %g s in %.3f s: %ld steps, %ld residual evaluations, "
                "%ld Jacobians, %ld error-test and %ld convergence failures\n",
                scene.name.c_str(), scene.run.ida.rtol, scene.run.ida.atol, ida.linear_solver.c_str(),
                report.state.t, report.wall_time, ida.steps, ida.residual_evaluations, ida.jacobian_evaluations,
                ida.error_test_failures, ida.nonlinear_convergence_failures);
    if (ida.linear_solver == "klu")
      std::printf("  KLU: %ld symbolic analyses of the Jacobian's pattern\n", ida.symbolic_analyses);
  } else {
    std::printf("%s: %ld steps of %g s in %.3f s (%.3g steps/s)\n", scene.name.c_str(), c.steps,
                scene.run.moreau_jean.step, report.wall_time, report.wall_time > 0 ? c.steps / report.wall_time : 0.0);
  }
  if (c.solves > 0)
    std::printf("  contact solver: %ld solves, %.2f sweeps on average, %d at most, max residual %.1e\n",
                c.solves, double(c.total_iterations) / c.solves, c.max_iterations, c.max_residual);
  if (c.not_converged > 0)
    std::printf("  warning: the contact solver stayed above its tolerance in %ld of %ld solves (first at t = %g s)\n",
                c.not_converged, c.solves, c.first_not_converged_time);
  if (scene.run.integrator == "quasi-static" || c.newton_iterations > 0)
    std::printf("  Newton: %ld iterations, %.2f a step on average, %d at most, %ld regularized, %ld held by contacts\n",
                c.newton_iterations, c.steps > 0 ? double(c.newton_iterations) / c.steps : 0.0, c.max_newton_iterations,
                c.newton_regularized, c.newton_held);
  const csim::PhaseTimers& t = report.state.timers;
  if (t.free_velocity + t.detection + t.assembly + t.solve + t.update > 0.0)
    std::printf("  phases (summary.json timers): %s %.3g s, detection %.3g s, assembly %.3g s, contact solve %.3g s, "
                "update %.3g s\n",
                scene.run.integrator == "quasi-static" ? "forces, tangent and its factorization" : "free velocity",
                t.free_velocity, t.detection, t.assembly, t.solve, t.update);
  if (c.cutbacks > 0)
    std::printf("  note: %ld load steps were taken again as two halves after Newton failed (integrator.max_cutbacks)\n",
                c.cutbacks);
  const csim::EnergyBalance& e = report.state.energy;
  if (scene.run.integrator == "quasi-static") {  // no inertia: the balance of work is not tracked
    std::printf("  energy: elastic %.6g J (the quasi-static stepper keeps no balance of work)\n", e.elastic);
    return;
  }
  std::printf("  energy: kinetic %.6g J, elastic %.6g J, work of loads %.6g J, contact dissipation %.6g J, "
              "numerical dissipation %.3g J, ",
              e.kinetic, e.elastic, e.work_of_loads, e.contact_dissipation, e.numerical_dissipation);
  if (e.damping_dissipation != 0.0) std::printf("damping dissipation %.6g J, ", e.damping_dissipation);
  std::printf("balance residual %.2e J\n", e.residual());
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

int run_compare(const Arguments& arguments, const std::string& file) {
  csim::CompareOptions options;
  options.scene_file = file;
  options.overrides = arguments.overrides;
  options.integrators = arguments.integrators;
  options.steps = arguments.steps;
  options.tolerances = arguments.tolerances;
  options.repeats = arguments.repeats;
  options.reference = arguments.reference;
  options.output_directory = arguments.output_directory;
  bool header_printed = false;  // not before the options and the scene are known to be good
  const csim::Comparison comparison = csim::run_comparison(options, [&](const csim::CompareRow& row) {
    if (!header_printed) print_compare_header();
    header_printed = true;
    print_compare_row(row);
  });
  const std::string directory =
      options.output_directory.empty() ? "out/" + comparison.scene_name + "-compare" : options.output_directory;
  csim::write_work_precision_csv(comparison, directory);
  csim::write_gnuplot_script(comparison, directory);
  const csim::PlotOutcome plot = csim::plot_work_precision(comparison, directory);
  if (!plot.produced) std::cerr << "csim: warning: no work_precision.png: " << plot.message << "\n";
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

void print_stress_row(const csim::StressRow& row) {
  char wall[32];
  std::snprintf(wall, sizeof wall, "%.3g", row.wall_time);
  std::printf("%-34s %-11s %-12s %-32s %-26s %9s %9s  %s\n", row.case_name().c_str(), row.integrator.c_str(),
              csim::outcome_name(row.outcome), row.worst_error_text().c_str(), row.energy_verdict().c_str(), wall,
              row.steps >= 0 ? std::to_string(row.steps).c_str() : "-", row.note().c_str());
  std::fflush(stdout);  // the table is the progress report of a long study
}

int run_stress(const Arguments& arguments, const std::string& file) {
  csim::StressOptions options;
  options.scene_file = file;
  options.sweeps_file = arguments.sweeps_file;
  options.overrides = arguments.overrides;
  options.only = arguments.only;
  bool header_printed = false;  // not before the sweeps file and the scene are known to be good
  const csim::StressStudy study = csim::run_stress(options, [&](const csim::StressRow& row) {
    if (!header_printed) print_stress_header();
    header_printed = true;
    print_stress_row(row);
  });
  const std::string directory =
      arguments.output_directory.empty() ? "out/" + study.scene_name + "-stress" : arguments.output_directory;
  csim::write_stability_markdown(study, directory);
  csim::write_stability_csv(study, directory);
  const auto violations = std::count_if(study.rows.begin(), study.rows.end(),
                                        [](const csim::StressRow& r) { return r.violates_invariant(); });
  std::printf("%s: %zu runs in %.1f s, %s (outputs in %s)\n", study.scene_name.c_str(), study.rows.size(),
              study.total_wall_time,
              violations == 0 ? "no invariant violated" : (std::to_string(violations) + " INVARIANT VIOLATIONS").c_str(),
              directory.c_str());
  return violations == 0 ? kPassed : kInvariantViolated;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments arguments;
  std::string error;
  if (argc >= 2 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
    usage(std::cout);
    return kPassed;
  }
  if (!parse(argc, argv, arguments, error)) {
    std::cerr << "csim: " << error << "\n";
    usage(std::cerr);
    return kBadInput;
  }
  const std::string file = scene_file(arguments.scene);
  try {
    if (arguments.command == "compare") return run_compare(arguments, file);
    if (arguments.command == "stress") return run_stress(arguments, file);
    const auto scene = csim::load_scene(file, arguments.overrides);
    if (arguments.command == "validate") {
      csim::make_stepper(*scene);  // what the stepper refuses at its construction, as run would
      std::printf("%s: valid (%zu bodies, %zu probes, %zu checks)\n", file.c_str(), scene->world.bodies.size(),
                  scene->run.probes.size(), scene->run.checks.size());
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
    const csim::RunReport report = csim::run_scene(*scene, options);
    if (!arguments.quiet) print_summary(*scene, report);
    print_checks(report.checks);
    std::printf("%s: %s (outputs in %s)\n", scene->name.c_str(), verdict(report.counts()).c_str(),
                options.output_directory.c_str());
    return report.passed() ? kPassed : kCheckFailed;
  } catch (const csim::SceneError& e) {
    std::cerr << "csim: error: " << e.what() << "\n";
  } catch (const csim::RunError& e) {
    std::cerr << "csim: " << file << ": numerical failure at t = " << e.time << " s: " << e.what() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "csim: " << file << ": " << e.what() << "\n";
  }
  return kBadInput;
}
