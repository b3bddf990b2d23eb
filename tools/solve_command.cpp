#include "tools/solve_command.h"

#include "contact/fclib_problem_format.h"
#include "contact/friction_contact_problem.h"
#include "contact/pgs_solver.h"
#include "contact/siconos_problem_format.h"
#include "tools/output/atomic_file.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <new>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace csim::cli {
namespace {

constexpr int kConverged = 0, kNotConverged = 1, kBadInput = 2;
constexpr const char* kCsimKeyword = "csim-friction-contact-problem";

// Bad input: the message is the whole line after "csim: ".
struct BadProblem : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The 1-based line of character `position` of `text` (its end: the last line with content).
int line_at(const std::string& text, std::size_t position) {
  position = std::min(position, text.size());
  while (position > 0 && std::isspace(static_cast<unsigned char>(text[position - 1]))) --position;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(position), '\n'));
}

// csim's own format. read_problem names what is wrong but not where: the line is that of the stream's
// position when it threw, just past the token it could not take.
FrictionContactProblem read_csim_problem(const std::string& file, const std::string& text) {
  std::istringstream in(text);
  try {
    return read_problem(in);
  } catch (const std::runtime_error& e) {
    in.clear();
    const std::streamoff position = in.tellg();
    std::string message = e.what();
    if (message.rfind("read_problem: ", 0) == 0) message.erase(0, std::strlen("read_problem: "));
    throw BadProblem(file + ":" + std::to_string(line_at(text, position < 0 ? text.size() : position)) + ": " +
                     message);
  }
}

FrictionContactProblem load_problem(const std::string& file) {
  std::error_code error;
  if (std::filesystem::is_directory(file, error)) throw BadProblem(file + ": a folder, not a problem file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw BadProblem(file + ": cannot open the problem file: " + std::strerror(errno));
  if (is_hdf5_file(file)) {
    try {
      return read_fclib_problem(file);
    } catch (const std::runtime_error& e) {
      throw BadProblem(file + ": " + e.what() + " (read as an FCLib HDF5 file)");
    }
  }
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw BadProblem(file + ": cannot read the problem file");
  std::istringstream first_word(text);
  std::string keyword;
  first_word >> keyword;
  if (keyword == kCsimKeyword) return read_csim_problem(file, text);
  std::istringstream siconos(text);
  try {
    return read_siconos_problem(siconos);
  } catch (const ProblemFileError& e) {
    throw BadProblem(file + ":" + std::to_string(e.line()) + ": " + e.message() +
                     " (read as Siconos' FrictionContactProblem format: the file does not start with " +
                     kCsimKeyword + ")");
  }
}

std::string solution_text(const Eigen::VectorXd& r) {
  std::string text;
  char number[32];
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    std::snprintf(number, sizeof number, "%.17g\n", r(i));
    text += number;
  }
  return text;
}

}  // namespace

int solve_command(const SolveArguments& arguments) {
  const std::string& file = arguments.problem;
  try {
    const FrictionContactProblem problem = load_problem(file);
    if (const std::string problem_with_it = inconsistency(problem); !problem_with_it.empty())
      throw BadProblem(file + ": " + problem_with_it);
    PgsParameters parameters;
    if (arguments.tolerance > 0.0) parameters.tolerance = arguments.tolerance;
    if (arguments.max_iterations > 0) parameters.max_iterations = arguments.max_iterations;
    const PgsSolver solver(parameters);
    Eigen::VectorXd r = Eigen::VectorXd::Zero(problem.size());
    PgsStatistics statistics;
    const auto start = std::chrono::steady_clock::now();
    try {
      statistics = solver.solve(problem, r);
    } catch (const std::invalid_argument& e) {  // e.g. equality rows on a W stored by blocks
      throw BadProblem(file + ": " + e.what());
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!arguments.solution_file.empty()) write_file_atomically(arguments.solution_file, solution_text(r));
    std::printf("converged=%s iterations=%d residual=%.3e time_s=%.6f\n", statistics.converged ? "yes" : "no",
                statistics.iterations, statistics.residual, seconds);
    return statistics.converged ? kConverged : kNotConverged;
  } catch (const BadProblem& e) {
    std::cerr << "csim: " << e.what() << "\n";
  } catch (const std::bad_alloc&) {
    std::cerr << "csim: " << file << ": out of memory (the system refused an allocation)\n";
  } catch (const std::system_error& e) {  // --out cannot be written (atomic_file.h names it)
    std::cerr << "csim: " << e.what() << "\n";
  }
  return kBadInput;
}

}  // namespace csim::cli
