// csim's command line (docs/contract.md), read with CLI11: one subcommand per job, each with only its own
// options and its own help (`csim run --help`, `csim help run`, `csim --help`, `csim help`).
#pragma once

#include "tools/solve_command.h"

#include <optional>
#include <string>
#include <vector>

namespace csim::cli {

// Exit statuses shared by every command (the file header of csim.cpp lists each command's own).
constexpr int kSuccess = 0, kBadInput = 2;

struct Arguments {
  std::string command, scene;
  std::vector<std::string> overrides;  // --set KEY=VALUE, in the order given
  std::string output_directory;        // --out; empty: the command's default under out/
  bool quiet = false;
  // compare
  std::vector<std::string> integrators;
  std::vector<double> steps, tolerances;  // s; dimensionless
  int repeats = 3;
  std::string reference = "auto";
  // stress, sweep
  std::string sweeps_file;
  std::vector<std::string> only;
  // sweep
  std::vector<std::string> set_lists, grids;  // KEY=V1,V2,..., in the order given
  bool no_case_outputs = false;
  // solve
  SolveArguments solve;
};

// Reads argv into `arguments`. Returns the exit status when csim must stop here: 0 once help is printed
// on stdout, 2 once a bad argument is reported in one line on stderr; nothing when a command is to run.
std::optional<int> parse_command_line(int argc, char** argv, Arguments& arguments);

}  // namespace csim::cli
