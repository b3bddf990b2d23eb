// csim: the command-line program (DESIGN.md §4).
//   csim run SCENE [--set KEY=VALUE]... [--out DIR] [--quiet]
//   csim validate SCENE [--set KEY=VALUE]...
//   csim dump-config SCENE [--set KEY=VALUE]...
// SCENE is a scene folder (holding scene.yaml) or a YAML file.
// Exit status: 0 all checks pass, 1 a check fails, 2 bad input or a numerical failure.
#include "engine/run.h"
#include "engine/scene/scene.h"
#include "engine/steppers/stepper.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace {

constexpr int kPassed = 0, kCheckFailed = 1, kBadInput = 2;

struct Arguments {
  std::string command, scene;
  std::vector<std::string> overrides;
  std::string output_directory;
  bool quiet = false;
};

void usage(std::ostream& out) {
  out << "usage: csim run SCENE [--set KEY=VALUE]... [--out DIR] [--quiet]\n"
         "       csim validate SCENE [--set KEY=VALUE]...\n"
         "       csim dump-config SCENE [--set KEY=VALUE]...\n"
         "SCENE is a scene folder (with scene.yaml) or a scene file.\n"
         "Exit status: 0 checks pass, 1 a check fails, 2 bad input or numerical failure.\n";
}

bool parse(int argc, char** argv, Arguments& a, std::string& error) {
  if (argc < 3) { error = "missing command or scene"; return false; }
  a.command = argv[1];
  if (a.command != "run" && a.command != "validate" && a.command != "dump-config") {
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
    } else if (arg == "--out" && a.command == "run") {
      const char* value = next("--out");
      if (!value) return false;
      a.output_directory = value;
    } else if (arg == "--quiet" && a.command == "run") {
      a.quiet = true;
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
      std::printf("  FAIL  %-22s %s\n", c.name.c_str(), c.note.c_str());
      continue;
    }
    const double relative = c.reference != 0.0 ? std::abs(c.error / c.reference) : std::abs(c.error);
    std::printf("  %s  %-22s %-8s value %-14.8g reference %-14.8g error %.2e (%s %.2e, tol abs %.1e rel %.1e) [%s]\n",
                c.passed ? "PASS" : "FAIL", c.name.c_str(), c.probe.c_str(), c.value, c.reference,
                c.error, c.reference != 0.0 ? "rel" : "abs", relative, c.absolute_tolerance,
                c.relative_tolerance, c.kind.c_str());
  }
}

void print_summary(const csim::Scene& scene, const csim::RunReport& report) {
  const csim::SolverCounters& c = report.state.counters;
  std::printf("%s: %ld steps of %g s in %.3f s (%.3g steps/s)\n", scene.name.c_str(), c.steps,
              scene.run.moreau_jean.step, report.wall_time, report.wall_time > 0 ? c.steps / report.wall_time : 0.0);
  if (c.solves > 0)
    std::printf("  contact solver: %ld solves, %.2f sweeps on average, %d at most, max residual %.1e\n",
                c.solves, double(c.total_iterations) / c.solves, c.max_iterations, c.max_residual);
  if (c.not_converged > 0)
    std::printf("  warning: the contact solver stayed above its tolerance in %ld of %ld solves (first at t = %g s)\n",
                c.not_converged, c.solves, c.first_not_converged_time);
  const csim::EnergyBalance& e = report.state.energy;
  std::printf("  energy: kinetic %.6g J, elastic %.6g J, work of loads %.6g J, contact dissipation %.6g J, "
              "numerical dissipation %.3g J, balance residual %.2e J\n",
              e.kinetic, e.elastic, e.work_of_loads, e.contact_dissipation, e.numerical_dissipation, e.residual());
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
    const auto scene = csim::load_scene(file, arguments.overrides);
    if (arguments.command == "validate") {
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
    std::printf("%s: %s (outputs in %s)\n", scene->name.c_str(),
                report.all_passed() ? "all checks passed" : "CHECKS FAILED", options.output_directory.c_str());
    return report.all_passed() ? kPassed : kCheckFailed;
  } catch (const csim::SceneError& e) {
    std::cerr << "csim: error: " << e.what() << "\n";
  } catch (const csim::RunError& e) {
    std::cerr << "csim: " << file << ": numerical failure at t = " << e.time << " s: " << e.what() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "csim: " << file << ": " << e.what() << "\n";
  }
  return kBadInput;
}
