// The solver's polish on frictional contact problems read from files (Siconos' text format or csim's):
// each problem solved from r = 0 with PgsSolver's defaults but the tolerance, W stored dense (the dense
// path: active set and Newton on dense LUs) and W stored by blocks (the sparse path: Newton on a sparse
// LU), so that the two polishes compare on the same problem; and W stored dense with the defaults, which
// route a large, mostly zero W to the sparse path (row "routed", "kept" when not routed). Per solve: sweeps, polishes, the polish's
// flops against the sweeps', its factorizations, whether it was cut at its budget, the relative residual
// (pgs_solver.h) and the time, median of `--repeats` solves alternating between the two storages [min-max].
//
//   bench_polish [--tolerance 1e-8] [--repeats 3] [--polish-budget 10] FILE...
//
// Siconos' test problems: numerics/src/FrictionContact/test/data of siconos/siconos
// (docs/contact-problems.md says how to extract them). A problem over 4096 rows is not stored dense.
#include "contact/friction_contact_problem.h"
#include "contact/pgs_solver.h"
#include "contact/siconos_problem_format.h"
#include "contact/sparse_pgs.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace {

csim::FrictionContactProblem read(const std::string& path) {
  std::ifstream in(path);
  std::string first;
  std::getline(in, first);
  in.seekg(0);
  if (first.rfind("csim-friction-contact-problem", 0) == 0) return csim::read_problem(in);
  return csim::read_siconos_problem(in);
}

csim::FrictionContactProblem stored(const csim::FrictionContactProblem& problem, csim::DelassusStorage storage) {
  csim::FrictionContactProblem copy = problem;
  copy.storage = storage;
  if (storage == csim::DelassusStorage::dense) {
    copy.W = problem.storage == csim::DelassusStorage::dense ? problem.W : Eigen::MatrixXd(problem.W_sparse);
    copy.W_sparse.resize(0, 0);
  } else {
    copy.W_sparse = problem.storage == csim::DelassusStorage::sparse ? problem.W_sparse
                                                                       : csim::block_sparse(problem.W, problem.dimension);
    copy.W.resize(0, 0);
  }
  return copy;
}

struct Run {
  csim::PgsStatistics statistics;
  std::vector<double> seconds;
};

void solve(const csim::FrictionContactProblem& problem, const csim::PgsParameters& parameters, Run& run) {
  Eigen::VectorXd r;
  const auto start = std::chrono::steady_clock::now();
  run.statistics = csim::PgsSolver(parameters).solve(problem, r);
  run.seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

void print(const char* name, const char* storage, int contacts, Run& run) {
  std::sort(run.seconds.begin(), run.seconds.end());
  const csim::PgsStatistics& s = run.statistics;
  std::printf("%-40s %6d %6s %7d %4d %9.2e %9.2e %5d %4s %9.1e %9.4f [%.4f-%.4f]\n", name, contacts, storage,
              s.iterations, s.polishes, s.sweep_work, s.polish_work, s.polish_factorizations, s.polish_cut ? "cut" : "-",
              s.residual, run.seconds[run.seconds.size() / 2], run.seconds.front(), run.seconds.back());
}

}  // namespace

int main(int argc, char** argv) {
  csim::PgsParameters parameters;
  parameters.tolerance = 1e-8;
  parameters.max_iterations = 100000;
  int repeats = 3;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--tolerance") && i + 1 < argc) parameters.tolerance = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--repeats") && i + 1 < argc) repeats = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--polish-budget") && i + 1 < argc) parameters.polish_budget = std::atof(argv[++i]);
    else files.emplace_back(argv[i]);
  }
  std::printf("%-40s %6s %6s %7s %4s %9s %9s %5s %4s %9s %9s\n", "problem", "contacts", "W", "sweeps", "pol",
              "sweep_fl", "polish_fl", "facts", "cut", "residual", "time_s [min-max]");
  for (const std::string& path : files) {
    const csim::FrictionContactProblem problem = read(path);
    const std::string name = path.substr(path.find_last_of('/') + 1);
    const bool dense = problem.size() <= 4096;
    const csim::FrictionContactProblem as_dense = dense ? stored(problem, csim::DelassusStorage::dense) : problem;
    const csim::FrictionContactProblem as_sparse = stored(problem, csim::DelassusStorage::sparse);
    // dense: the dense path (route_sparse off); routed: W stored dense with the defaults, which route a
    // large, mostly zero W to the sparse path (pgs_solver.h); sparse: W stored by blocks.
    csim::PgsParameters dense_path = parameters;
    dense_path.route_sparse = false;
    Run dense_run, routed_run, sparse_run;
    for (int k = 0; k < repeats; ++k) {  // alternating, so that the machine's drift is shared
      if (dense) solve(as_dense, dense_path, dense_run);
      if (dense) solve(as_dense, parameters, routed_run);
      solve(as_sparse, parameters, sparse_run);
    }
    if (dense) print(name.c_str(), "dense", problem.contacts, dense_run);
    if (dense) print(name.c_str(), routed_run.statistics.routed_to_sparse ? "routed" : "kept", problem.contacts, routed_run);
    print(name.c_str(), "sparse", problem.contacts, sparse_run);
  }
  return 0;
}
