// The whitespace-separated tokens of a Gmsh MSH 4.1 ASCII file (gmsh_reader.h), read as a stream: the
// file is never held whole (a buffer of kBufferSize bytes, the current token's first kKeptCharacters),
// and every failure throws FemError naming the file and the line (path:line: ...).
//
// What is refused here, whatever the section:
//   a byte that no text file holds (NUL, or another control character than tab, CR, LF, FF, VT): the
//     file is binary (a binary MSH, a file of zeros), named with its line and column;
//   a number that is not one, or out of the range its field allows: the integers are parsed as 64-bit
//     (std::from_chars, which reports overflow) and then checked against the field's own range, so that
//     no value is ever narrowed (an element type 2^32 + 3 is not 3).
// A token is quoted in messages to its first kQuotedCharacters characters, then "…" and its length.
#pragma once

#include <cstddef>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace csim {

class MshTokens {
 public:
  static constexpr std::size_t kBufferSize = 1 << 16;     // bytes read at once
  static constexpr std::size_t kKeptCharacters = 256;     // of a token: no number or marker is longer
  static constexpr std::size_t kQuotedCharacters = 40;    // of a token, in a message

  // Opens the file (refusing what is not a regular file before opening: a FIFO would block).
  explicit MshTokens(const std::string& path);

  const std::string& path() const { return path_; }
  // The file's size in bytes: a bound on what it can hold (no count it announces is believed beyond it).
  std::size_t file_size() const { return file_size_; }
  // The line of the current position, 1-based; at the end of the file, its last line.
  int line() const;
  // The line of the next token (or the last line at the end of the file).
  int token_line();
  bool at_end();

  // The next token, its first kKeptCharacters characters (token_length() says how long it is); `what`
  // says what was expected, for the message at the end of the file.
  const std::string& word(std::string_view what);
  std::size_t token_length() const { return token_length_; }

  // An integer in [low, high]; `what` names the field in the message.
  long long integer(std::string_view what, long long low, long long high);
  int count(std::string_view what);          // a count, in [0, INT_MAX]
  int dimension(std::string_view what);      // an entity dimension, in [0, 3]
  int int_value(std::string_view what);      // a Gmsh int (a type, an entity or physical tag): [INT_MIN, INT_MAX]
  long long tag(std::string_view what);      // a node or element tag (size_t in Gmsh): [1, LLONG_MAX]
  long long tag_bound(std::string_view what);  // the smallest or largest tag, 0 when there is none
  double real(std::string_view what);        // finite

  // A double-quoted name as in $PhysicalNames (it may contain spaces, not a line break).
  std::string quoted(std::string_view what);
  void expect(std::string_view marker);
  // Skips a section we do not read, up to its end marker.
  void skip_section(std::string_view name);

  // `text` as a message quotes it: its first kQuotedCharacters characters, "…" and its length beyond.
  static std::string excerpt(const std::string& text, std::size_t length);
  static std::string excerpt(const std::string& text) { return excerpt(text, text.size()); }
  // The current token, as above.
  std::string token_excerpt() const { return excerpt(token_, token_length_); }

  [[noreturn]] void fail(const std::string& message) const { fail_at(line(), message); }
  [[noreturn]] void fail_at(int line, const std::string& message) const;

 private:
  // The next byte without consuming it; −1 at the end of the file.
  int peek() {
    if (position_ == filled_ && !refill()) return -1;
    return static_cast<unsigned char>(buffer_[position_]);
  }
  bool refill();
  void advance(char c);  // consumes c, the byte at the position
  void skip_space();
  // A byte that no text holds, at the current position: refused (see the header).
  [[noreturn]] void fail_binary(int byte) const;
  static bool is_space(int c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
  static bool is_binary(int c) { return c >= 0 && c < 0x20 && c != '\n' && !is_space(c); }

  std::string path_;
  std::ifstream file_;
  std::size_t file_size_ = 0;
  std::vector<char> buffer_;
  std::size_t position_ = 0, filled_ = 0;
  std::size_t offset_ = 0;        // bytes of the file before buffer_[0]
  std::size_t line_start_ = 0;    // the current line's first byte, as an offset in the file
  int line_ = 1;
  bool ended_with_newline_ = false;  // the last byte consumed was a line break
  std::string token_;
  std::size_t token_length_ = 0;
};

}  // namespace csim
