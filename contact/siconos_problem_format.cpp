#include "contact/siconos_problem_format.h"

#include "contact/whole_blocks.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <istream>
#include <iterator>
#include <string_view>
#include <system_error>
#include <vector>

namespace csim {
namespace {

// Storage numbers of NM_write_in_file (NM_types.h: NM_DENSE, NM_SPARSE_BLOCK, NM_SPARSE).
constexpr long long kDense = 0, kSparseBlock = 1;  // NM_SPARSE = 2 is the rest
// More contacts than any problem Siconos' tests or FCLib hold by far; it keeps d · nc in an int.
constexpr long long kMaxContacts = 1LL << 26;

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

// The whole input in memory, read token by token (as fscanf does) or line by line (as the fgets of
// CSparseMatrix_new_from_file does), knowing the line of the last token for the error messages.
class Cursor {
 public:
  explicit Cursor(std::istream& in) : text_(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()) {}

  std::string_view token(const char* what) {
    while (position_ < text_.size() && is_space(text_[position_])) advance();
    // At the end, the line of the last token stays the one named: the file's last line of content.
    if (position_ == text_.size()) fail(std::string("unexpected end of input while reading ") + what);
    token_line_ = line_;
    const std::size_t first = position_;
    while (position_ < text_.size() && !is_space(text_[position_])) ++position_;
    return std::string_view(text_).substr(first, position_ - first);
  }

  void expect(std::string_view keyword, const char* what) {
    const std::string_view found = token(what);
    if (found != keyword)
      fail("expected '" + std::string(keyword) + "' in " + what + ", found '" + std::string(found) + "'");
  }

  // A finite double as fscanf's %le reads it (a leading '+' allowed).
  double number(const char* what) {
    std::string_view text = token(what);
    if (text.size() > 1 && text[0] == '+') text.remove_prefix(1);
    double value = 0.0;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
    if (result.ec != std::errc() || result.ptr != text.data() + text.size())
      fail("malformed number '" + std::string(text) + "' in " + what);
    if (!std::isfinite(value)) fail("non-finite number '" + std::string(text) + "' in " + what);
    return value;
  }

  long long integer(const char* what, long long minimum, long long maximum) {
    const std::string_view text = token(what);
    long long value = 0;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
    if (result.ec != std::errc() || result.ptr != text.data() + text.size())
      fail("malformed integer '" + std::string(text) + "' for " + what);
    if (value < minimum || value > maximum)
      fail(std::string(what) + " is " + std::to_string(value) + ", expected " + std::to_string(minimum) +
           " to " + std::to_string(maximum));
    return value;
  }

  // The rest of the current line (without its end), the cursor moved to the start of the next.
  std::string_view rest_of_line(const char* what) {
    token_line_ = line_;
    if (position_ == text_.size()) fail(std::string("unexpected end of input while reading ") + what);
    const std::size_t first = position_;
    while (position_ < text_.size() && text_[position_] != '\n') ++position_;
    const std::string_view line = std::string_view(text_).substr(first, position_ - first);
    if (position_ < text_.size()) advance();
    return line;
  }

  // Tokens left, counted up to `limit`.
  int tokens_left(int limit) {
    int count = 0;
    while (count < limit) {
      while (position_ < text_.size() && is_space(text_[position_])) advance();
      if (position_ == text_.size()) break;
      token_line_ = line_;
      while (position_ < text_.size() && !is_space(text_[position_])) ++position_;
      ++count;
    }
    return count;
  }

  [[noreturn]] void fail(const std::string& message) const { throw ProblemFileError(token_line_, message); }

 private:
  void advance() {
    if (text_[position_] == '\n') ++line_;
    ++position_;
  }

  std::string text_;
  std::size_t position_ = 0;
  int line_ = 1;        // line of position_
  int token_line_ = 1;  // line of the last token read
};

using Entry = Eigen::Triplet<double>;

// NM_DENSE after storage, size0 and size1: the sizes again, then the entries column by column.
Eigen::MatrixXd read_dense(Cursor& cursor, int size) {
  cursor.integer("the dense matrix's row count", size, size);
  cursor.integer("the dense matrix's column count", size, size);
  // Read before the matrix is allocated, so a corrupt header fails at the end of the input, not in a
  // huge allocation.
  std::vector<double> values;
  for (std::int64_t k = 0; k < static_cast<std::int64_t>(size) * size; ++k) values.push_back(cursor.number("W"));
  return Eigen::Map<const Eigen::MatrixXd>(values.data(), size, size);  // column-major, as Siconos' matrix0
}

// The cumulated sizes of SBM block rows or columns: strictly increasing to `size`, on contact boundaries.
std::vector<long long> block_boundaries(Cursor& cursor, long long count, int size, int dimension,
                                        const char* what) {
  std::vector<long long> boundaries;
  for (long long k = 0; k < count; ++k) {
    const long long boundary = cursor.integer(what, (boundaries.empty() ? 0 : boundaries.back()) + 1, size);
    if (boundary % dimension != 0)
      cursor.fail(std::string(what) + " " + std::to_string(boundary) + " splits a contact of dimension " +
                  std::to_string(dimension));
    boundaries.push_back(boundary);
  }
  if (boundaries.empty() || boundaries.back() != size)
    cursor.fail(std::string(what) + " end at " + std::to_string(boundaries.empty() ? 0 : boundaries.back()) +
                ", expected " + std::to_string(size));
  return boundaries;
}

// NM_SPARSE_BLOCK: SBM_write_in_file's layout (see the header).
SparseDelassus read_sparse_block(Cursor& cursor, int size, int dimension) {
  const long long block_count =
      cursor.integer("the number of blocks (nbblocks)", 1, static_cast<long long>(size) * size);
  const long long block_rows = cursor.integer("the number of block rows", 1, size);
  const long long block_columns = cursor.integer("the number of block columns", 1, size);
  const std::vector<long long> row_end = block_boundaries(cursor, block_rows, size, dimension, "block row sizes");
  const std::vector<long long> column_end =
      block_boundaries(cursor, block_columns, size, dimension, "block column sizes");
  const long long filled1 = cursor.integer("filled1 (block row pointers)", 1, block_rows + 1);
  cursor.integer("filled2 (stored blocks)", block_count, block_count);
  std::vector<long long> row_start;
  for (long long k = 0; k < filled1; ++k)
    row_start.push_back(
        cursor.integer("a block row pointer (index1_data)", row_start.empty() ? 0 : row_start.back(), block_count));
  if (row_start.front() != 0 || row_start.back() != block_count)
    cursor.fail("block row pointers run from " + std::to_string(row_start.front()) + " to " +
                std::to_string(row_start.back()) + ", expected 0 to " + std::to_string(block_count));
  std::vector<long long> block_column;
  for (long long k = 0; k < block_count; ++k)
    block_column.push_back(cursor.integer("a block column index (index2_data)", 0, block_columns - 1));

  std::vector<Entry> entries;
  for (long long block_row = 0; block_row + 1 < filled1; ++block_row) {
    const long long first_row = block_row ? row_end[block_row - 1] : 0;
    std::vector<long long> seen(block_column.begin() + row_start[block_row],
                                block_column.begin() + row_start[block_row + 1]);
    std::sort(seen.begin(), seen.end());
    if (std::adjacent_find(seen.begin(), seen.end()) != seen.end())
      cursor.fail("block row " + std::to_string(block_row) + " holds the same block column twice");
    for (long long block = row_start[block_row]; block < row_start[block_row + 1]; ++block) {
      cursor.integer("a block's number", block, block);
      const long long column = block_column[block];
      const long long first_column = column ? column_end[column - 1] : 0;
      const long long rows = row_end[block_row] - first_row, columns = column_end[column] - first_column;
      for (long long j = 0; j < columns; ++j)
        for (long long i = 0; i < rows; ++i)  // column-major within a block (SBM_get_value)
          entries.emplace_back(static_cast<int>(first_row + i), static_cast<int>(first_column + j), cursor.number("W"));
    }
  }
  return whole_blocks(size, dimension, entries);
}

// NM_SPARSE: NSM_write_in_file's origin, then CSparseMatrix_print_in_file's text.
SparseDelassus read_csparse(Cursor& cursor, int size, int dimension) {
  cursor.integer("the sparse matrix's origin", 0, 4);
  cursor.rest_of_line("the sparse matrix's origin");
  if (cursor.rest_of_line("CSparse's version line").find("CSparse") == std::string_view::npos)
    cursor.fail("expected CSparse's version line");
  const std::string_view header = cursor.rest_of_line("CSparse's size line");
  enum class Kind { columns, rows, triplets } kind = Kind::columns;
  std::string_view shape = header;
  shape.remove_prefix(std::min(shape.find_first_not_of(' '), shape.size()));
  if (shape.starts_with("triplet:")) kind = Kind::triplets;
  if (shape.starts_with("csr:")) kind = Kind::rows;
  if (kind != Kind::columns) shape.remove_prefix(shape.find(':') + 1);
  shape.remove_prefix(std::min(shape.find_first_not_of(' '), shape.size()));
  int m = -1, n = -1;
  if (std::sscanf(std::string(shape).c_str(), "%d-by-%d", &m, &n) != 2 || m != size || n != size)
    cursor.fail("expected a " + std::to_string(size) + "-by-" + std::to_string(size) + " matrix, found '" +
                std::string(header) + "'");
  std::vector<Entry> entries;
  if (kind == Kind::triplets) {
    const std::size_t at = header.find("nnz:");
    long long count = -1;
    if (at == std::string_view::npos || std::sscanf(std::string(header.substr(at + 4)).c_str(), "%lld", &count) != 1 ||
        count < 0)
      cursor.fail("no entry count (nnz) in '" + std::string(header) + "'");
    for (long long k = 0; k < count; ++k) {
      const int row = static_cast<int>(cursor.integer("a row index", 0, size - 1));
      const int column = static_cast<int>(cursor.integer("a column index", 0, size - 1));
      cursor.expect(":", "a triplet entry");
      entries.emplace_back(row, column, cursor.number("W"));
    }
    return whole_blocks(size, dimension, entries);
  }
  const char* keyword = kind == Kind::columns ? "col" : "row";
  long long next = 0;
  for (int outer = 0; outer < size; ++outer) {
    cursor.expect(keyword, "a compressed column or row");
    cursor.integer(kind == Kind::columns ? "the column number" : "the row number", outer, outer);
    cursor.expect(":", "a compressed column or row");
    cursor.expect("locations", "a compressed column or row");
    cursor.integer("the first location", next, next);
    cursor.expect("to", "a compressed column or row");
    const long long last = cursor.integer("the last location", next - 1, next + size - 1);
    for (; next <= last; ++next) {
      const int inner = static_cast<int>(cursor.integer("an entry's index", 0, size - 1));
      cursor.expect(":", "an entry");
      const double value = cursor.number("W");
      entries.push_back(kind == Kind::columns ? Entry(inner, outer, value) : Entry(outer, inner, value));
    }
  }
  return whole_blocks(size, dimension, entries);
}

}  // namespace

FrictionContactProblem read_siconos_problem(std::istream& in) {
  Cursor cursor(in);
  FrictionContactProblem problem;
  problem.dimension = static_cast<int>(cursor.integer("the dimension", 2, 3));
  problem.contacts = static_cast<int>(cursor.integer("the number of contacts", 1, kMaxContacts));
  const int size = problem.size();
  const long long storage = cursor.integer("the matrix storage (0 dense, 1 sparse-block, 2 sparse)", 0, 2);
  cursor.integer("the matrix's row count (d times the contacts)", size, size);
  cursor.integer("the matrix's column count (d times the contacts)", size, size);
  if (storage == kDense) {
    problem.W = read_dense(cursor, size);
  } else {
    problem.storage = DelassusStorage::sparse;
    problem.W_sparse = storage == kSparseBlock ? read_sparse_block(cursor, size, problem.dimension)
                                               : read_csparse(cursor, size, problem.dimension);
  }
  problem.b.resize(size);
  for (int i = 0; i < size; ++i) problem.b(i) = cursor.number("q");
  problem.mu.resize(problem.contacts);
  for (Eigen::Vector2d& mu : problem.mu) {
    const double value = cursor.number("mu");
    if (value < 0.0) cursor.fail("negative friction coefficient " + std::to_string(value));
    mu = Eigen::Vector2d(value, value);
  }
  if (cursor.tokens_left(2) > 1)
    cursor.fail("more after mu than a FrictionContactProblem holds (a GlobalFrictionContactProblem file?)");
  return problem;
}

}  // namespace csim
