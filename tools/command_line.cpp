#include "tools/command_line.h"

#include "contact/pgs_solver.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <climits>
#include <iostream>

namespace csim::cli {

namespace {

const std::vector<std::string> kCommands{"run", "validate", "dump-config", "compare", "stress", "sweep", "solve", "help"};

void add_scene(CLI::App& command, Arguments& a) {
  command.add_option("SCENE", a.scene, "a scene folder (holding scene.yaml) or a scene file")->required();
}

void add_overrides(CLI::App& command, Arguments& a) {
  // One value per --set: a vector option would otherwise take the SCENE that follows as a second one.
  command.add_option("--set", a.overrides, "override one value of the scene; repeatable (--set time.end=2)")
      ->type_name("KEY=VALUE")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

// KEY=V1,V2,...: one list per use, the option repeatable (the commas are the study's to read).
void add_value_lists(CLI::App& command, const std::string& name, std::vector<std::string>& lists, const std::string& help) {
  command.add_option(name, lists, help)
      ->type_name("KEY=V1,V2,...")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

void add_output(CLI::App& command, Arguments& a, const std::string& default_folder) {
  command
      .add_option("--out", a.output_directory,
                  "output folder (default " + default_folder + "), replaced whole when the command ends")
      ->type_name("DIR");
}

// A comma-separated list, one item per comma; several uses of the option add up.
template <typename T>
CLI::Option* add_list(CLI::App& command, const std::string& name, std::vector<T>& items, const std::string& help) {
  return command.add_option(name, items, help)
      ->type_name("LIST")
      ->delimiter(',')
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

// CLI11's PositiveNumber would print the range it checks, up to DBL_MAX in full.
const CLI::Validator kPositive(
    [](std::string& text) {
      double x = 0.0;
      return CLI::detail::lexical_cast(text, x) && x > 0.0 ? std::string() : "'" + text + "' is not a positive number";
    },
    "POSITIVE");

const char* const kStopped =
    "130, 143 or 129: stopped by SIGINT, SIGTERM or SIGHUP (the output folder is left as it was).";

void define(CLI::App& app, Arguments& a, std::string& help_topic) {
  app.description("csim: nonsmooth contact dynamics. `csim help COMMAND` or `csim COMMAND --help` for one command.");
  app.require_subcommand(1);
  app.footer("SCENE is a scene folder (holding scene.yaml) or a scene file, e.g. scenes/sdnv104-rigid.");

  CLI::App* run = app.add_subcommand("run", "run a scene, write its outputs and evaluate its checks");
  add_scene(*run, a);
  add_overrides(*run, a);
  add_output(*run, a, "out/<scene>");
  run->add_flag("--quiet", a.quiet, "print only the checks and the verdict");
  run->footer("Writes DIR/summary.json, DIR/probes.csv and, for elastic bodies, DIR/paraview/.\n"
              "Exit status: 0 checks passed (at least one evaluated, none failed, the others excluded by\n"
              "their only_if) or a scene without checks ran to its end (a plain simulation), 1 not a pass\n"
              "(a check failed or could not be evaluated, or none applies),\n"
              "2 bad input, a numerical failure (DIR then holds the outputs up to the failure, its\n"
              "summary.json saying \"status\": \"failed\") or an environment failure (a full disk: the\n"
              "system's reason);\n" +
              std::string(kStopped));

  CLI::App* validate = app.add_subcommand("validate", "check a scene (and what run would refuse) without running it");
  add_scene(*validate, a);
  add_overrides(*validate, a);
  validate->footer("Exit status: 0 valid, 2 not (the message names the file, the line and the key).");

  CLI::App* dump = app.add_subcommand("dump-config", "print the effective scene, every default written in");
  add_scene(*dump, a);
  add_overrides(*dump, a);
  dump->footer("Exit status: 0, or 2 on bad input.");

  CLI::App* compare = app.add_subcommand("compare", "the work-precision study: error against wall time per integrator");
  add_scene(*compare, a);
  add_overrides(*compare, a);
  add_list(*compare, "--integrators", a.integrators, "integrators to compare: moreau-jean, generalized-alpha, ida, ida-events")
      ->required();
  add_list(*compare, "--steps", a.steps, "time steps of the moreau-jean and generalized-alpha runs (s)")->check(kPositive);
  add_list(*compare, "--tolerances", a.tolerances, "rtol = atol of the ida and ida-events runs")
      ->check(kPositive);
  compare->add_option("--repeats", a.repeats, "runs per configuration, for the median wall time (default 3)")
      ->type_name("N")
      ->check(CLI::Range(1, 1000000));
  compare->add_option("--reference", a.reference, "what the errors are measured against (default auto)")
      ->type_name("auto|analytical|ida-events|moreau-jean")
      ->check(CLI::IsMember({"auto", "analytical", "ida-events", "moreau-jean"}));
  add_output(*compare, a, "out/<scene>-compare");
  compare->footer("moreau-jean and generalized-alpha run once per step, ida and ida-events once per tolerance, each N times; writes\n"
                  "DIR/work_precision.csv, .gp and .png. Under mpirun or srun the runs are spread over the ranks, one per\n"
                  "core with --bind-to core (docs/scaling-out.md).\n"
                  "Exit status: 0 every run succeeded, 1 some run failed (recorded in its row), 2 bad input;\n" +
                  std::string(kStopped));

  CLI::App* stress = app.add_subcommand("stress", "the stability study: each case of a sweeps file with each integrator");
  add_scene(*stress, a);
  add_overrides(*stress, a);
  stress->add_option("--sweeps", a.sweeps_file, "the sweeps file (default stress.yaml beside the scene)")
      ->type_name("FILE");
  add_list(*stress, "--only", a.only, "run only these sweeps of the file");
  add_output(*stress, a, "out/<scene>-stress");
  stress->footer("Writes DIR/stability.md and DIR/stability.csv. Under mpirun or srun the cases are spread over the ranks\n"
                 "(docs/scaling-out.md).\n"
                 "Exit status: 0 no run violated an invariant (failed checks and IDA stops are only reported),\n"
                 "1 some run did, 2 bad input (sweeps file, --only, --set); " + std::string(kStopped));

  CLI::App* sweep = app.add_subcommand("sweep", "a parameter study: the scene once per case, one CSV row per case");
  add_scene(*sweep, a);
  add_overrides(*sweep, a);
  add_value_lists(*sweep, "--set-list", a.set_lists,
                  "lists taken together: case i sets the i-th value of each; repeatable");
  add_value_lists(*sweep, "--grid", a.grids, "every combination with the other grids (the first varies slowest); repeatable");
  sweep->add_option("--sweeps", a.sweeps_file, "the cases from a sweeps file in the format of csim stress")
      ->type_name("FILE");
  sweep->add_flag("--no-case-outputs", a.no_case_outputs, "write no case-NNNN/ folders, only sweep.csv");
  add_output(*sweep, a, "out/<scene>-sweep");
  sweep->footer("Writes DIR/sweep.csv and, per case, what csim run writes into DIR/case-NNNN/ (NNNN: the case's row).\n"
                "Under mpirun or srun the cases are spread over the ranks (docs/scaling-out.md).\n"
                "Exit status: 0 every case passed its checks, 1 some case did not (recorded in its row),\n"
                "2 bad input (lists, sweeps file, --set, a key no case could set); " + std::string(kStopped));

  const PgsParameters defaults;
  CLI::App* solve = app.add_subcommand("solve", "solve one frictional contact problem read from a file");
  solve->add_option("PROBLEM", a.solve.problem, "the problem: csim's text format, Siconos' FrictionContactProblem format or FCLib's HDF5")
      ->required();
  solve->add_option("--tolerance", a.solve.tolerance,
                    "relative residual at which the solve stops (default " + CLI::detail::to_string(defaults.tolerance) + ")")
      ->type_name("T")
      ->check(kPositive);
  solve->add_option("--max-iterations", a.solve.max_iterations,
                    "Gauss-Seidel sweeps at most (default " + std::to_string(defaults.max_iterations) + ")")
      ->type_name("N")
      ->check(CLI::Range(1, INT_MAX));
  solve->add_option("--out", a.solve.solution_file, "write r there, one number a line, in the problem's row order")
      ->type_name("FILE");
  solve->footer("Prints one line: converged=yes|no iterations=N residual=R time_s=T (T: the solve alone, reading excluded).\n"
                "FILE is written completely or not at all. Exit status: 0 converged, 1 not converged, 2 bad input\n"
                "(the message names the file and the line) or FILE cannot be written.");

  CLI::App* help = app.add_subcommand("help", "print the help of csim or of one command");
  help->add_option("COMMAND", help_topic, "the command to explain");
}

// The help text of one command, its usage line starting with "csim".
std::string command_help(const CLI::App& app, const std::string& command) {
  const CLI::App* sub = app.get_subcommand(command);
  return sub->get_formatter()->make_help(sub, "csim " + command, CLI::AppFormatMode::Normal);
}

int bad_argument(const std::string& where, const std::string& message) {
  std::cerr << "csim" << where << ": " << message << " (see csim help" << where << ")\n";
  return kBadInput;
}

}  // namespace

std::optional<int> parse_command_line(int argc, char** argv, Arguments& arguments) {
  // Named before CLI11 reads it: its own message for a stray word would list every word after it.
  if (argc >= 2 && argv[1][0] != '-' &&
      std::find(kCommands.begin(), kCommands.end(), argv[1]) == kCommands.end())
    return bad_argument("", "unknown command '" + std::string(argv[1]) +
                                "' (commands: run, validate, dump-config, compare, stress, sweep, solve, help)");
  // CLI11 drops the empty items of a delimited list: `--steps 1e-2,,1e-3` would quietly run two steps.
  for (int i = 2; i < argc; ++i) {
    const std::string word = argv[i];
    for (const char* option : {"--integrators", "--steps", "--tolerances", "--only"}) {
      const std::string name = option;
      std::string list;
      if (word == name && i + 1 < argc) list = argv[i + 1];
      else if (word.rfind(name + "=", 0) == 0) list = word.substr(name.size() + 1);
      else continue;
      if (list.empty() || list.front() == ',' || list.back() == ',' || list.find(",,") != std::string::npos)
        return bad_argument(" " + std::string(argv[1]), name + ": an empty item in the list '" + list + "'");
    }
  }
  CLI::App app("", "csim");
  std::string help_topic;
  define(app, arguments, help_topic);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return kSuccess;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.help("", CLI::AppFormatMode::All);
    return kSuccess;
  } catch (const CLI::ParseError& e) {
    const auto selected = app.get_subcommands();
    if (argc < 2) return bad_argument("", "missing command (run, validate, dump-config, compare, stress, sweep, solve, help)");
    return bad_argument(selected.empty() ? "" : " " + selected.front()->get_name(), e.what());
  }
  arguments.command = app.get_subcommands().front()->get_name();
  if (arguments.command != "help") return std::nullopt;
  if (help_topic.empty()) {
    std::cout << app.get_formatter()->make_help(&app, "csim", CLI::AppFormatMode::Normal);
    return kSuccess;
  }
  if (std::find(kCommands.begin(), kCommands.end(), help_topic) == kCommands.end())
    return bad_argument("", "help: no command '" + help_topic +
                                "' (commands: run, validate, dump-config, compare, stress, sweep, solve)");
  std::cout << command_help(app, help_topic);
  return kSuccess;
}

}  // namespace csim::cli
