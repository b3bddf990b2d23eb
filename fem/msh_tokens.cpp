#include "fem/msh_tokens.h"

#include "fem/mesh.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <system_error>

namespace csim {

MshTokens::MshTokens(const std::string& path) : path_(path) {
  // Before opening: a FIFO would block, a device be read without end, a directory read as empty.
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    throw FemError(path + ": not a regular file (a directory, a FIFO or a device holds no Gmsh mesh)");
  file_.open(path, std::ios::binary);
  if (!file_) throw FemError(path + ": cannot open the Gmsh mesh file");
  file_size_ = static_cast<std::size_t>(std::filesystem::file_size(path, error));
  if (error) file_size_ = 0;
  buffer_.resize(kBufferSize);
}

bool MshTokens::refill() {
  if (!file_.is_open() || file_.eof()) return false;
  offset_ += filled_;
  file_.read(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  filled_ = static_cast<std::size_t>(file_.gcount());
  position_ = 0;
  if (file_.bad()) fail("read error");
  return filled_ > 0;
}

int MshTokens::line() const {
  // At the end of a file whose last line ends with a line break, the position is past it: name that line.
  const bool at_file_end = position_ == filled_ && (!file_.is_open() || file_.eof());
  return at_file_end && ended_with_newline_ && line_ > 1 ? line_ - 1 : line_;
}

void MshTokens::advance(char c) {
  ++position_;
  ended_with_newline_ = c == '\n';
  if (c == '\n') {
    ++line_;
    line_start_ = offset_ + position_;
  }
}

void MshTokens::skip_space() {
  for (int c = peek(); c == '\n' || is_space(c); c = peek()) advance(static_cast<char>(c));
}

int MshTokens::token_line() {
  skip_space();
  return line();
}

bool MshTokens::at_end() {
  skip_space();
  const int c = peek();
  if (is_binary(c)) fail_binary(c);
  return c < 0;
}

void MshTokens::fail_binary(int byte) const {
  char code[8];
  std::snprintf(code, sizeof code, "0x%02X", static_cast<unsigned>(byte));
  const std::size_t column = offset_ + position_ - line_start_ + 1;
  fail_at(line_, std::string("byte ") + code + (byte == 0 ? " (NUL)" : "") + " at column " + std::to_string(column) +
                     ": not a text file (a Gmsh mesh is read as MSH 4.1 ASCII text; a binary MSH or a file of zeros "
                     "is not)");
}

const std::string& MshTokens::word(std::string_view what) {
  if (at_end()) fail("unexpected end of file while reading " + std::string(what) + " (truncated file?)");
  token_.clear();
  token_length_ = 0;
  for (int c = peek(); c >= 0 && c != '\n' && !is_space(c); c = peek()) {
    if (is_binary(c)) fail_binary(c);
    if (token_.size() < kKeptCharacters) token_.push_back(static_cast<char>(c));
    ++token_length_;
    advance(static_cast<char>(c));
  }
  return token_;
}

std::string MshTokens::excerpt(const std::string& text, std::size_t length) {
  if (length <= kQuotedCharacters) return text;
  return text.substr(0, kQuotedCharacters) + "… (" + std::to_string(length) + " characters)";
}

long long MshTokens::integer(std::string_view what, long long low, long long high) {
  const std::string& token = word(what);
  long long value = 0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  const bool whole = token_length_ == token.size() && end == token.data() + token.size();
  if (error == std::errc::result_out_of_range && whole)
    fail(std::string(what) + " " + token_excerpt() + " is out of range [" + std::to_string(low) + ", " + std::to_string(high) +
         "]");
  if (error != std::errc() || !whole) fail("expected an integer (" + std::string(what) + "), found '" + token_excerpt() + "'");
  if (value < low || value > high)
    fail(std::string(what) + " " + std::to_string(value) + " is out of range [" + std::to_string(low) + ", " +
         std::to_string(high) + "]");
  return value;
}

int MshTokens::count(std::string_view what) {
  return static_cast<int>(integer(what, 0, std::numeric_limits<int>::max()));
}

int MshTokens::dimension(std::string_view what) { return static_cast<int>(integer(what, 0, 3)); }

int MshTokens::int_value(std::string_view what) {
  return static_cast<int>(integer(what, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
}

long long MshTokens::tag(std::string_view what) {
  return integer(what, 1, std::numeric_limits<long long>::max());
}

long long MshTokens::tag_bound(std::string_view what) {
  return integer(what, 0, std::numeric_limits<long long>::max());
}

double MshTokens::real(std::string_view what) {
  const std::string& token = word(what);
  double value = 0.0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (error != std::errc() || token_length_ != token.size() || end != token.data() + token.size() ||
      !std::isfinite(value))
    fail("expected a finite number (" + std::string(what) + "), found '" + token_excerpt() + "'");
  return value;
}

std::string MshTokens::quoted(std::string_view what) {
  if (at_end() || peek() != '"') fail("expected a quoted " + std::string(what));
  advance('"');
  std::string value;
  for (int c = peek();; c = peek()) {
    if (c < 0 || c == '\n') fail("unterminated quoted " + std::string(what));
    if (is_binary(c)) fail_binary(c);
    advance(static_cast<char>(c));
    if (c == '"') return value;
    value.push_back(static_cast<char>(c));
  }
}

void MshTokens::expect(std::string_view marker) {
  const std::string& token = word(marker);
  if (token != marker || token_length_ != token.size()) fail("expected " + std::string(marker) + ", found '" + token_excerpt() + "'");
}

void MshTokens::skip_section(std::string_view name) {
  const std::string end = "$End" + std::string(name.substr(1));
  for (;;) {
    const std::string& token = word(end);
    if (token == end && token_length_ == token.size()) return;
  }
}

void MshTokens::fail_at(int line, const std::string& message) const {
  throw FemError(path_ + ":" + std::to_string(line) + ": " + message);
}

}  // namespace csim
