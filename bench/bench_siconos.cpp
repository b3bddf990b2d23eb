// csim's PgsSolver against Siconos' NSGS on frictional contact problems in Siconos' text format
// (docs/contact-problems.md): every problem file of a folder (Siconos' numerics/src/FrictionContact/test/data),
// both solvers from r = 0 to the same tolerance, both judged by one yardstick, Siconos' natural-map error
// (fc3d_compute_error / fc2d_compute_error, relative to max(‖q‖, ‖r‖, ‖u‖)), computed by Siconos itself.
//
//   bench_siconos DIR [--tolerance 1e-8] [--max-iterations 100000] [--timeout 120] [--dense-limit 4096]
//                     [--repeats 3] [--omega W]
// (--omega: csim's relaxation, used throughout as a scene's contact_solver.omega is; without it, the
// default: PgsParameters::relax_sparse.)
//
// Each solve runs in a child process killed after --timeout seconds; the time is the solve's alone
// (reading, conversions and the error excluded), the median of --repeats solves alternating between the
// two solvers (a solver that took over 10 s, or did not finish, is not repeated), ± half the spread.
// csim reads each file with its own reader (contact/siconos_problem_format.h), Siconos with
// frictionContact_newFromFile; the two readings are compared first (q, mu, and W x for a fixed x), a note
// saying so when they differ. A solver that refuses a
// W stored by blocks gets a dense copy up to --dense-limit rows (noted in the table), none above.
// Siconos 4.4's fc2d driver takes no CSparse W (storage 2): it gets the block-sparse copy made by its own
// SBM_from_csparse. FCLib's HDF5 files are read by csim alone (Debian's Siconos is built without FCLIB):
// Siconos gets a block-sparse copy of that reading. Files named GFC*/gfc* (global problems, another
// format) and FCLib's global problems are listed, not run. OpenBLAS runs one thread (the program re-executes
// itself with OPENBLAS_NUM_THREADS=1 when it is unset).
// A problem with ‖q‖ ≤ DBL_EPSILON is solved by both, and judged, with q scaled by a power of 2 to
// ‖q‖ in [0.5, 1) (noted in the table): see at_unit_scale below.
#include "contact/fclib_problem_format.h"
#include "contact/friction_contact_problem.h"
#include "contact/pgs_solver.h"
#include "contact/siconos_problem_format.h"
#include "bench/siconos_error.h"

#include <FrictionContactProblem.h>
#include <Friction_cst.h>
#include <NonSmoothDrivers.h>
#include <NumericsMatrix.h>
#include <SolverOptions.h>
#include <SparseBlockMatrix.h>
#define restrict __restrict  // fc2d_compute_error.h is C99
#include <fc2d_compute_error.h>
#undef restrict
#include <fc3d_compute_error.h>

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using csim::bench::siconos_error;

struct Options {
  std::string directory;
  double tolerance = 1e-8;
  int max_iterations = 100000;  // both solvers: the time limit decides
  double timeout = 120.0;       // s
  int dense_limit = 4096;       // rows of a dense copy of W for a solver that refuses it by blocks (128 MiB)
  int repeats = 3;              // solves of each problem by each solver, alternating; none after one over 10 s
  double omega = 0.0;           // csim's relaxation when > 0 (and relax_sparse off); 0: the default
};

// What a child sends back through its pipe: a plain struct.
struct Outcome {
  enum State { solved, refused, failed, timed_out } state = failed;
  double seconds = 0.0, error = NAN;  // seconds: the median of the repeats
  double spread = 0.0;                 // (slowest − fastest) / 2 / median of the repeats
  int iterations = 0;
  char note[200] = "";
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Runs `work` in a child process, killed after `timeout` seconds. Siconos' messages go to /dev/null.
Outcome in_child(double timeout, const std::function<Outcome()>& work) {
  int channel[2];
  if (pipe(channel) != 0) throw std::runtime_error("pipe failed");
  std::fflush(stdout);
  const pid_t child = fork();
  if (child < 0) throw std::runtime_error("fork failed");
  if (child == 0) {
    close(channel[0]);
    if (FILE* null = std::freopen("/dev/null", "w", stdout)) (void)null;
    Outcome outcome;
    try {
      outcome = work();
    } catch (const std::exception& e) {
      outcome.state = Outcome::failed;
      std::snprintf(outcome.note, sizeof outcome.note, "%s", e.what());
    }
    const ssize_t written = write(channel[1], &outcome, sizeof outcome);
    _exit(written == static_cast<ssize_t>(sizeof outcome) ? 0 : 1);
  }
  close(channel[1]);
  pollfd ready{channel[0], POLLIN, 0};
  Outcome outcome;
  const int polled = poll(&ready, 1, static_cast<int>(timeout * 1000.0));
  if (polled == 0) {
    kill(child, SIGKILL);
    outcome.state = Outcome::timed_out;
  } else if (read(channel[0], &outcome, sizeof outcome) != static_cast<ssize_t>(sizeof outcome)) {
    outcome = Outcome{};
    outcome.state = Outcome::failed;
  }
  close(channel[0]);
  int status = 0;
  waitpid(child, &status, 0);
  if (outcome.state == Outcome::failed && outcome.note[0] == '\0') {
    if (WIFSIGNALED(status)) std::snprintf(outcome.note, sizeof outcome.note, "crashed (signal %d)", WTERMSIG(status));
    else std::snprintf(outcome.note, sizeof outcome.note, "exited %d", WEXITSTATUS(status));
  }
  return outcome;
}

int rows(const ::FrictionContactProblem& problem) { return problem.dimension * problem.numberOfContacts; }

Outcome solve_with_csim(const csim::FrictionContactProblem& loaded, ::FrictionContactProblem& siconos,
                        const Options& options) {
  csim::PgsParameters parameters;
  parameters.tolerance = options.tolerance;
  parameters.max_iterations = options.max_iterations;
  if (options.omega > 0.0) {
    parameters.omega = options.omega;
    parameters.relax_sparse = false;
  }
  const csim::PgsSolver solver(parameters);
  Outcome outcome;
  Eigen::VectorXd r = Eigen::VectorXd::Zero(loaded.size());
  csim::PgsStatistics statistics;
  auto start = std::chrono::steady_clock::now();
  try {
    statistics = solver.solve(loaded, r);
  } catch (const std::invalid_argument& refusal) {
    if (loaded.storage != csim::DelassusStorage::sparse || loaded.size() > options.dense_limit) {
      outcome.state = Outcome::refused;
      std::snprintf(outcome.note, sizeof outcome.note, "%s", refusal.what());
      return outcome;
    }
    csim::FrictionContactProblem dense = loaded;
    dense.storage = csim::DelassusStorage::dense;
    dense.W = Eigen::MatrixXd(loaded.W_sparse);
    dense.W_sparse = csim::SparseDelassus();
    std::snprintf(outcome.note, sizeof outcome.note, "csim on a dense copy of W");
    r.setZero();
    start = std::chrono::steady_clock::now();
    statistics = solver.solve(dense, r);
  }
  outcome.seconds = seconds_since(start);
  outcome.iterations = statistics.iterations;
  outcome.error = siconos_error(siconos, r, options.tolerance);
  outcome.state = Outcome::solved;
  return outcome;
}

Outcome solve_with_nsgs(::FrictionContactProblem& problem, const Options& options) {
  SolverOptions* solver_options =
      solver_options_create(problem.dimension == 3 ? SICONOS_FRICTION_3D_NSGS : SICONOS_FRICTION_2D_NSGS);
  solver_options->dparam[SICONOS_DPARAM_TOL] = options.tolerance;
  solver_options->iparam[SICONOS_IPARAM_MAX_ITER] = options.max_iterations;
  const int n = rows(problem);
  std::vector<double> reaction(n, 0.0), velocity(n, 0.0);
  const auto start = std::chrono::steady_clock::now();
  if (problem.dimension == 3) fc3d_driver(&problem, reaction.data(), velocity.data(), solver_options);
  else fc2d_driver(&problem, reaction.data(), velocity.data(), solver_options);
  Outcome outcome;
  outcome.seconds = seconds_since(start);
  outcome.iterations = solver_options->iparam[SICONOS_IPARAM_ITER_DONE];
  solver_options_delete(solver_options);
  outcome.error = siconos_error(problem, Eigen::Map<Eigen::VectorXd>(reaction.data(), n), options.tolerance);
  outcome.state = Outcome::solved;
  return outcome;
}

// "" when the two readings agree: q and mu to the bit, W x to round-off for x_i = sin(i + 1).
std::string compare_readings(const csim::FrictionContactProblem& ours, ::FrictionContactProblem& theirs) {
  const int n = rows(theirs);
  if (theirs.dimension != ours.dimension || theirs.numberOfContacts != ours.contacts)
    return "dimension or contact count";
  for (int i = 0; i < n; ++i)
    if (ours.b(i) != theirs.q[i]) return "q(" + std::to_string(i) + ")";
  for (int c = 0; c < ours.contacts; ++c)
    if (ours.mu[c](0) != theirs.mu[c]) return "mu(" + std::to_string(c) + ")";
  Eigen::VectorXd x(n), y_theirs = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i) x(i) = std::sin(1.0 + i);
  NM_gemv(1.0, theirs.M, x.data(), 0.0, y_theirs.data());
  const Eigen::VectorXd y_ours = ours.storage == csim::DelassusStorage::dense ? Eigen::VectorXd(ours.W * x)
                                                                              : Eigen::VectorXd(ours.W_sparse * x);
  const double scale = std::max(y_theirs.cwiseAbs().maxCoeff(), 1e-300);
  if ((y_ours - y_theirs).cwiseAbs().maxCoeff() > 1e-13 * scale) return "W x";
  return "";
}

// max |W − Wᵀ| / max |W|: 0 for a symmetric W (the table's "skew").
double skew(const csim::FrictionContactProblem& problem) {
  if (problem.storage == csim::DelassusStorage::dense) {
    const double scale = std::max(problem.W.cwiseAbs().maxCoeff(), 1e-300);
    return (problem.W - problem.W.transpose()).cwiseAbs().maxCoeff() / scale;
  }
  const csim::SparseDelassus transpose = problem.W_sparse.transpose();
  const csim::SparseDelassus difference = problem.W_sparse - transpose;
  double largest = 1e-300, largest_difference = 0.0;
  for (int k = 0; k < problem.W_sparse.nonZeros(); ++k)
    largest = std::max(largest, std::abs(problem.W_sparse.valuePtr()[k]));
  for (int k = 0; k < difference.nonZeros(); ++k)
    largest_difference = std::max(largest_difference, std::abs(difference.valuePtr()[k]));
  return largest_difference / largest;
}

std::string cell(const Outcome& outcome, bool time) {
  char text[64];
  switch (outcome.state) {
    case Outcome::timed_out: return "timeout";
    case Outcome::refused: return "refused";
    case Outcome::failed: return "failed";
    case Outcome::solved:
      if (time && outcome.spread > 0.0)
        std::snprintf(text, sizeof text, "%.3g ±%.0f%%", outcome.seconds, 100.0 * outcome.spread);
      else if (time) std::snprintf(text, sizeof text, "%.3g", outcome.seconds);
      else std::snprintf(text, sizeof text, "%.1e", outcome.error);
      return text;
  }
  return "";
}

// The last run, its time the median of the runs' (all solved) and their spread.
Outcome median(const std::vector<Outcome>& runs) {
  Outcome outcome = runs.back();
  if (outcome.state != Outcome::solved) return outcome;
  std::vector<double> seconds;
  for (const Outcome& run : runs) seconds.push_back(run.seconds);
  std::sort(seconds.begin(), seconds.end());
  const std::size_t n = seconds.size();
  outcome.seconds = n % 2 ? seconds[n / 2] : 0.5 * (seconds[n / 2 - 1] + seconds[n / 2]);
  outcome.spread = n > 1 ? 0.5 * (seconds.back() - seconds.front()) / outcome.seconds : 0.0;
  return outcome;
}

bool converged(const Outcome& outcome, double tolerance) {
  return outcome.state == Outcome::solved && outcome.error <= tolerance;
}

const char* storage_name(int storage) {
  return storage == NM_DENSE ? "dense" : storage == NM_SPARSE_BLOCK ? "SBM" : "CSparse";
}

// The power of 2 that brings ‖q‖ into [0.5, 1) when ‖q‖ ≤ DBL_EPSILON, else 1. Siconos' error is relative
// to max(‖q‖, ‖r‖, ‖u‖) only when that exceeds DBL_EPSILON (fc2d_compute_error, fc3d_compute_error):
// below, it is absolute, and so is NSGS's stopping test, which uses it. On Siconos'
// fc2d_granularflowonwall_00667_00000 (‖q‖ = 4.3e-18) NSGS then stops after one iteration at an error of
// 3.7e-19, where the same r is 0.087 off the law relative to the problem's own scale. The law is
// positively homogeneous (q scaled by s scales every solution r and its u by s), and a power of 2 scales
// doubles exactly, so on the scaled problem both solvers solve the file's problem, judged relative to
// its scale, as on every other file (csim's residual, relative, is the same at both scales: 41 sweeps).
double at_unit_scale(const Eigen::VectorXd& q) {
  const double norm_q = q.norm();
  if (!(norm_q > 0.0) || norm_q > DBL_EPSILON) return 1.0;
  int exponent = 0;
  std::frexp(norm_q, &exponent);  // norm_q = f · 2^exponent, f in [0.5, 1)
  return std::ldexp(1.0, -exponent);
}

// Siconos' problem from csim's reading of it, W stored by blocks (SBM_from_csparse drops explicit zeros).
::FrictionContactProblem* siconos_copy(const csim::FrictionContactProblem& problem) {
  const int n = problem.size();
  NumericsMatrix* entries = NM_create(NM_SPARSE, n, n);
  NM_triplet_alloc(entries, problem.W_sparse.nonZeros());
  for (int row = 0; row < n; ++row)
    for (csim::SparseDelassus::InnerIterator it(problem.W_sparse, row); it; ++it)
      NM_entry(entries, row, static_cast<int>(it.col()), it.value());
  SparseBlockStructuredMatrix* blocks = SBM_new();
  SBM_from_csparse(problem.dimension, NM_csc(entries), blocks);
  auto* q = static_cast<double*>(std::malloc(sizeof(double) * n));
  auto* mu = static_cast<double*>(std::malloc(sizeof(double) * problem.contacts));
  for (int i = 0; i < n; ++i) q[i] = problem.b(i);
  for (int c = 0; c < problem.contacts; ++c) mu[c] = problem.mu[c](0);
  return frictionContactProblem_new_with_data(problem.dimension, problem.contacts, NM_new_SBM(n, n, blocks), q, mu);
}

Options parse(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    const bool has_value = i + 1 < argc;
    if (word == "--tolerance" && has_value) options.tolerance = std::atof(argv[++i]);
    else if (word == "--max-iterations" && has_value) options.max_iterations = std::atoi(argv[++i]);
    else if (word == "--timeout" && has_value) options.timeout = std::atof(argv[++i]);
    else if (word == "--dense-limit" && has_value) options.dense_limit = std::atoi(argv[++i]);
    else if (word == "--repeats" && has_value) options.repeats = std::atoi(argv[++i]);
    else if (word == "--omega" && has_value) options.omega = std::atof(argv[++i]);
    else if (options.directory.empty() && word[0] != '-') options.directory = word;
    else throw std::invalid_argument("unknown argument '" + word + "'");
  }
  if (options.directory.empty() || !(options.tolerance > 0) || options.max_iterations < 1 || !(options.timeout > 0) ||
      options.repeats < 1 || !(options.omega == 0.0 || (options.omega > 0.0 && options.omega < 2.0)))
    throw std::invalid_argument(
        "usage: bench_siconos DIR [--tolerance 1e-8] [--max-iterations 100000] [--timeout 120] [--dense-limit 4096] "
        "[--repeats 3] [--omega W, in (0, 2)]");
  return options;
}

}  // namespace

int main(int argc, char** argv) {
  if (!std::getenv("OPENBLAS_NUM_THREADS")) {  // read when the library loads: set it, then start again
    setenv("OPENBLAS_NUM_THREADS", "1", 1);
    setenv("OMP_NUM_THREADS", "1", 1);
    execv("/proc/self/exe", argv);
  }
  Options options;
  try {
    options = parse(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_siconos: %s\n", e.what());
    return 2;
  }
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(options.directory))
    if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());

  std::printf("tolerance %g, at most %d iterations, %g s a solve, from r = 0, median of %d; "
              "error: Siconos' natural map\n\n",
              options.tolerance, options.max_iterations, options.timeout, options.repeats);
  std::printf("| problem | d | contacts | W | symmetric (skew) | csim s | csim error | csim sweeps | NSGS s "
              "| NSGS error | NSGS iterations | csim/NSGS |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::vector<std::string> notes, skipped;
  int problems = 0, csim_solved = 0, nsgs_solved = 0, both = 0, csim_no_slower = 0;
  for (const auto& path : files) {
    const std::string name = path.filename().string();
    if (name.rfind("GFC", 0) == 0 || name.rfind("gfc", 0) == 0) {
      skipped.push_back(name + ": a global problem (GlobalFrictionContactProblem format), not run");
      continue;
    }
    csim::FrictionContactProblem ours;
    ::FrictionContactProblem* theirs = nullptr;
    std::string storage;
    try {
      if (csim::is_hdf5_file(path)) {
        ours = csim::read_fclib_problem(path);
        theirs = siconos_copy(ours);
        storage = "FCLib";
        notes.push_back(name + ": NSGS on an SBM copy of csim's reading (Debian's Siconos reads no HDF5)");
      } else {
        std::ifstream in(path);
        ours = csim::read_siconos_problem(in);
      }
    } catch (const std::exception& e) {
      skipped.push_back(name + ": " + e.what());
      continue;
    }
    if (!theirs) {
      FILE* file = std::fopen(path.c_str(), "r");
      theirs = frictionContact_newFromFile(file);
      std::fclose(file);
      storage = storage_name(theirs->M->storageType);
      const std::string disagreement = compare_readings(ours, *theirs);
      if (!disagreement.empty()) notes.push_back(name + ": the two readers disagree on " + disagreement);
    }
    if (theirs->M->storageType == NM_SPARSE) {  // fc2d_driver (4.4) takes dense and SBM only
      SparseBlockStructuredMatrix* blocks = SBM_new();
      SBM_from_csparse(theirs->dimension, NM_csc(theirs->M), blocks);
      theirs->M = NM_new_SBM(rows(*theirs), rows(*theirs), blocks);
      notes.push_back(name + ": NSGS on Siconos' SBM_from_csparse copy of W");
    }
    if (const double scale = at_unit_scale(ours.b); scale != 1.0) {
      ours.b *= scale;
      for (int i = 0; i < rows(*theirs); ++i) theirs->q[i] *= scale;
      char text[200];
      std::snprintf(text, sizeof text,
                    ": ‖q‖ = %.2g ≤ DBL_EPSILON, where Siconos' error is absolute: both solvers on q scaled by 2^%d "
                    "(exact; every solution scales alike)",
                    ours.b.norm() / scale, static_cast<int>(std::lround(std::log2(scale))));
      notes.push_back(name + text);
    }
    std::vector<Outcome> csim_runs, nsgs_runs;
    for (int repeat = 0; repeat < options.repeats; ++repeat) {
      const bool csim_again = csim_runs.empty() || (csim_runs.back().state == Outcome::solved &&
                                                    csim_runs.back().seconds < 10.0);
      const bool nsgs_again = nsgs_runs.empty() || (nsgs_runs.back().state == Outcome::solved &&
                                                    nsgs_runs.back().seconds < 10.0);
      if (csim_again)
        csim_runs.push_back(in_child(options.timeout, [&] { return solve_with_csim(ours, *theirs, options); }));
      if (nsgs_again) nsgs_runs.push_back(in_child(options.timeout, [&] { return solve_with_nsgs(*theirs, options); }));
    }
    const Outcome csim_outcome = median(csim_runs), nsgs_outcome = median(nsgs_runs);
    for (const Outcome* outcome : {&csim_outcome, &nsgs_outcome})
      if (outcome->note[0] != '\0')
        notes.push_back(name + ": " + (outcome == &csim_outcome ? "csim: " : "NSGS: ") + outcome->note);
    ++problems;
    const bool csim_ok = converged(csim_outcome, options.tolerance);
    const bool nsgs_ok = converged(nsgs_outcome, options.tolerance);
    csim_solved += csim_ok;
    nsgs_solved += nsgs_ok;
    std::string ratio = "–";
    if (csim_ok && nsgs_ok) {
      ++both;
      char text[32];
      std::snprintf(text, sizeof text, "%.2f", csim_outcome.seconds / nsgs_outcome.seconds);
      ratio = text;
      csim_no_slower += csim_outcome.seconds <= nsgs_outcome.seconds;
    }
    char skew_text[32];
    const double skew_value = skew(ours);
    if (skew_value == 0.0) std::snprintf(skew_text, sizeof skew_text, "yes");
    else std::snprintf(skew_text, sizeof skew_text, "no (%.0e)", skew_value);
    std::printf("| %s | %d | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", name.c_str(), ours.dimension,
                ours.contacts, storage.c_str(), skew_text, cell(csim_outcome, true).c_str(),
                cell(csim_outcome, false).c_str(),
                csim_outcome.state == Outcome::solved ? std::to_string(csim_outcome.iterations).c_str() : "",
                cell(nsgs_outcome, true).c_str(), cell(nsgs_outcome, false).c_str(),
                nsgs_outcome.state == Outcome::solved ? std::to_string(nsgs_outcome.iterations).c_str() : "",
                ratio.c_str());
    std::fflush(stdout);
    frictionContactProblem_free(theirs);
  }
  std::printf("\n%d problems: csim reached %g on %d, NSGS on %d; on the %d both reached, csim was no slower on %d.\n",
              problems, options.tolerance, csim_solved, nsgs_solved, both, csim_no_slower);
  for (const std::string& note : notes) std::printf("- %s\n", note.c_str());
  for (const std::string& line : skipped) std::printf("- not run: %s\n", line.c_str());
  return 0;
}
