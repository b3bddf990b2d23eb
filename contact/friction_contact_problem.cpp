#include "contact/friction_contact_problem.h"

#include "contact/whole_blocks.h"

#include <charconv>
#include <istream>
#include <ostream>
#include <stdexcept>
#include <string>
#include <system_error>

// File layout (whitespace between tokens is free; one line per item for readability):
//
//   csim-friction-contact-problem 1
//   dimension 3
//   contacts 2
//   equalities 1
//   mu
//   0.3 0.3
//   0.1 0
//   q
//   q_0 q_1 ... q_{n-1}
//   W
//   W_00 ... W_0,n-1          (one row per line)
//   ...
//   end
//
// or, for storage sparse, in place of the W section, the stored entries as triplets in row order
// (0-based row and column; explicit zeros kept, so that the pattern of whole blocks round-trips):
//   W sparse 5                (the number of entries)
//   0 0 2.5
//   ...
//   end
// A problem read from a `W sparse` section is stored sparse, its pattern completed to whole blocks
// (whole_blocks.h) when it has no equality rows. Files with a dense W section load as before.
//
// Numbers are written with std::to_chars' shortest round-trip form (never fewer digits than needed for
// an exact round trip, so at most max_digits10 = 17 significant digits, and "0.3" rather than
// "0.29999999999999999") and read with std::from_chars: both are locale-independent, and nan/inf
// survive, so a problem that went wrong in a run replays bit for bit.

namespace csim {
namespace {

constexpr const char* kKeyword = "csim-friction-contact-problem";
constexpr int kVersion = 1;
// A corrupt count must not turn into a multi-gigabyte allocation of W: 65536 rows is already 32 GiB.
constexpr long long kMaxRows = 65536;
// A sparse W costs its entries, not rows²: only b and mu grow with the rows.
constexpr long long kMaxSparseRows = 1LL << 26;

std::string format_number(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  if (result.ec != std::errc()) throw std::runtime_error("write_problem: cannot format a number");
  return std::string(buffer, result.ptr);
}

class TokenReader {
 public:
  explicit TokenReader(std::istream& in) : in_(in) {}

  std::string next(const char* what) {
    std::string token;
    if (!(in_ >> token)) fail(std::string("unexpected end of input while reading ") + what);
    return token;
  }

  void expect(const char* keyword) {
    const std::string token = next(keyword);
    if (token != keyword)
      fail(std::string("expected keyword '") + keyword + "', found '" + token + "'");
  }

  double number(const char* what) { return number_of(next(what), what); }

  double number_of(const std::string& token, const char* what) const {
    double value = 0.0;
    const char* first = token.data();
    const char* last = first + token.size();
    // from_chars rejects a leading '+', which printf-style writers produce in exponents only.
    const auto result = std::from_chars(first, last, value);
    if (result.ec != std::errc() || result.ptr != last)
      fail(std::string("malformed number '") + token + "' in " + what);
    return value;
  }

  long long integer(const char* what) {
    const std::string token = next(what);
    long long value = 0;
    const char* first = token.data();
    const char* last = first + token.size();
    const auto result = std::from_chars(first, last, value);
    if (result.ec != std::errc() || result.ptr != last)
      fail(std::string("malformed integer '") + token + "' for " + what);
    return value;
  }

  [[noreturn]] void fail(const std::string& message) const {
    throw std::runtime_error("read_problem: " + message);
  }

 private:
  std::istream& in_;
};

// The `W sparse` section after its keyword: the entry count, then row, column and value per entry.
void read_sparse_section(TokenReader& reader, FrictionContactProblem& problem) {
  const long long n = problem.size();
  const long long count = reader.integer("the count of W's entries");
  if (count < 0 || (n > 0 && count / n > n)) reader.fail("W sparse: entry count " + std::to_string(count) + " does not fit " +
                                                         std::to_string(n) + " rows");
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(std::min<long long>(count, 1LL << 24)));
  for (long long e = 0; e < count; ++e) {
    const long long row = reader.integer("W sparse row");
    const long long column = reader.integer("W sparse column");
    if (row < 0 || row >= n || column < 0 || column >= n)
      reader.fail("W sparse: entry (" + std::to_string(row) + ", " + std::to_string(column) + ") outside " +
                  std::to_string(n) + "x" + std::to_string(n));
    entries.emplace_back(static_cast<int>(row), static_cast<int>(column), reader.number("W sparse value"));
  }
  problem.storage = DelassusStorage::sparse;
  if (problem.equalities == 0) {
    problem.W_sparse = whole_blocks(static_cast<int>(n), problem.dimension, entries);
  } else {
    problem.W_sparse.resize(n, n);
    problem.W_sparse.setFromTriplets(entries.begin(), entries.end());
  }
  problem.W_sparse.makeCompressed();
}

}  // namespace

std::string inconsistency(const FrictionContactProblem& problem) {
  if (problem.dimension != 2 && problem.dimension != 3)
    return "dimension must be 2 or 3, not " + std::to_string(problem.dimension);
  if (problem.contacts < 0 || problem.equalities < 0) return "negative contact or equality count";
  const Eigen::Index n = problem.size();
  const bool sparse = problem.storage == DelassusStorage::sparse;
  const Eigen::Index rows = sparse ? problem.W_sparse.rows() : problem.W.rows();
  const Eigen::Index cols = sparse ? problem.W_sparse.cols() : problem.W.cols();
  if (rows != n || cols != n)
    return std::string(sparse ? "W_sparse" : "W") + " is " + std::to_string(rows) + "x" + std::to_string(cols) +
           ", expected " + std::to_string(n) + "x" + std::to_string(n);
  if (problem.b.size() != n)
    return "b has " + std::to_string(problem.b.size()) + " rows, expected " + std::to_string(n);
  if (static_cast<int>(problem.mu.size()) != problem.contacts)
    return "mu has " + std::to_string(problem.mu.size()) + " entries, expected " +
           std::to_string(problem.contacts);
  if (const BodyBlockDelassus& blocks = problem.body_blocks; !blocks.empty()) {
    if (!sparse || problem.equalities > 0) return "body_blocks are given for a sparse W without equality rows only";
    const std::size_t contacts = static_cast<std::size_t>(problem.contacts);
    if (blocks.body.size() != contacts ||
        blocks.scaled_rows.size() != 2 * contacts * problem.dimension * BodyBlockDelassus::kBodySize)
      return "body_blocks do not have one entry per contact";
    for (const std::array<int, 2>& bodies : blocks.body)
      for (const int b : bodies)
        if (b < -1 || b >= blocks.bodies) return "body_blocks name a body outside [0, bodies)";
  }
  return "";
}

void write_problem(std::ostream& out, const FrictionContactProblem& problem) {
  if (const std::string problem_with_it = inconsistency(problem); !problem_with_it.empty())
    throw std::runtime_error("write_problem: " + problem_with_it);
  const Eigen::Index n = problem.size();
  // Built in a string so the caller's stream flags and locale play no part in the numbers.
  std::string text;
  text += std::string(kKeyword) + " " + std::to_string(kVersion) + "\n";
  text += "dimension " + std::to_string(problem.dimension) + "\n";
  text += "contacts " + std::to_string(problem.contacts) + "\n";
  text += "equalities " + std::to_string(problem.equalities) + "\n";
  text += "mu\n";
  for (const Eigen::Vector2d& mu : problem.mu)
    text += format_number(mu(0)) + " " + format_number(mu(1)) + "\n";
  text += "q\n";
  for (Eigen::Index i = 0; i < n; ++i) text += (i ? " " : "") + format_number(problem.b(i));
  if (problem.storage == DelassusStorage::sparse) {
    text += "\nW sparse " + std::to_string(problem.W_sparse.nonZeros()) + "\n";
    for (Eigen::Index i = 0; i < n; ++i)
      for (SparseDelassus::InnerIterator it(problem.W_sparse, i); it; ++it)
        text += std::to_string(it.row()) + " " + std::to_string(it.col()) + " " + format_number(it.value()) + "\n";
  } else {
    text += "\nW\n";
    for (Eigen::Index i = 0; i < n; ++i) {
      for (Eigen::Index j = 0; j < n; ++j) text += (j ? " " : "") + format_number(problem.W(i, j));
      text += "\n";
    }
  }
  text += "end\n";
  out << text;
  if (!out) throw std::runtime_error("write_problem: stream write failed");
}

FrictionContactProblem read_problem(std::istream& in) {
  TokenReader reader(in);
  reader.expect(kKeyword);
  const long long version = reader.integer("the format version");
  if (version != kVersion)
    reader.fail("unsupported format version " + std::to_string(version) + " (this build reads " +
                std::to_string(kVersion) + ")");

  FrictionContactProblem problem;
  reader.expect("dimension");
  const long long dimension = reader.integer("dimension");
  if (dimension != 2 && dimension != 3)
    reader.fail("dimension must be 2 or 3, not " + std::to_string(dimension));
  reader.expect("contacts");
  const long long contacts = reader.integer("contacts");
  reader.expect("equalities");
  const long long equalities = reader.integer("equalities");
  if (contacts < 0 || equalities < 0) reader.fail("negative contact or equality count");
  if (contacts > kMaxSparseRows || equalities > kMaxSparseRows || dimension * contacts + equalities > kMaxSparseRows)
    reader.fail("problem size exceeds " + std::to_string(kMaxSparseRows) + " rows (corrupt header?)");
  problem.dimension = static_cast<int>(dimension);
  problem.contacts = static_cast<int>(contacts);
  problem.equalities = static_cast<int>(equalities);
  const Eigen::Index n = problem.size();

  reader.expect("mu");
  problem.mu.resize(problem.contacts);
  for (Eigen::Vector2d& mu : problem.mu) {
    mu(0) = reader.number("mu");
    mu(1) = reader.number("mu");
  }
  reader.expect("q");
  problem.b.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) problem.b(i) = reader.number("q");
  reader.expect("W");
  const std::string first = reader.next("W");
  if (n == 0 && first == "end") return problem;  // an empty dense W: its first token closes the file
  if (first == "sparse") {
    read_sparse_section(reader, problem);
  } else {
    if (n > kMaxRows)
      reader.fail("a dense W of " + std::to_string(n) + " rows exceeds " + std::to_string(kMaxRows) +
                  " (corrupt header? a large problem is stored `W sparse`)");
    problem.W.resize(n, n);
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index j = 0; j < n; ++j) problem.W(i, j) = (i == 0 && j == 0) ? reader.number_of(first, "W") : reader.number("W");
  }
  // The closing keyword catches a W with more entries than the header announced.
  reader.expect("end");
  return problem;
}

}  // namespace csim
