// csim solve PROBLEM [--tolerance T] [--max-iterations N] [--out FILE] (docs/contract.md, "solve"):
// one frictional contact problem, read from a file, solved by PgsSolver.
//
// PROBLEM is an FCLib HDF5 file (fclib_problem_format.h: the file starts with HDF5's signature), in csim's
// own text format (write_problem, friction_contact_problem.h: the file starts with
// `csim-friction-contact-problem`) or in Siconos' FrictionContactProblem text format
// (siconos_problem_format.h: any other file). Prints one line
//   converged=yes|no iterations=N residual=R time_s=T
// (N sweeps, R the solver's relative residual, pgs_solver.h; T the solve's wall time in seconds, reading
// excluded) and, with --out, writes r (the problem's rows in order, one number a line, %.17g) to FILE,
// completely or not at all (atomic_file.h). Exit status: 0 converged, 1 not converged, 2 bad input
// (the message names the file and, for a malformed text file, the line; for an HDF5 file, the dataset) or
// a file that cannot be written.
#pragma once

#include <string>

namespace csim::cli {

struct SolveArguments {
  std::string problem;        // the problem file
  double tolerance = -1.0;    // relative residual; ≤ 0: PgsParameters' default
  int max_iterations = -1;    // sweeps; ≤ 0: PgsParameters' default
  std::string solution_file;  // --out; empty: r is not written
};

int solve_command(const SolveArguments& arguments);

}  // namespace csim::cli
