// The record of one case of a study, as the study runner carries it from the rank that ran the case to
// rank 0 (study_runner.h): a flat byte string of fixed-width numbers and length-prefixed strings.
// Doubles travel as their bits, so that a row read back on rank 0 is the row the case produced, bit
// for bit, and the study's outputs are those of a serial run. Both ends run the same binary: no byte
// order or versioning is needed.
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace csim {

class RecordWriter {
 public:
  RecordWriter& number(double x) { return raw(&x, sizeof x); }
  RecordWriter& integer(std::int64_t n) { return raw(&n, sizeof n); }
  RecordWriter& flag(bool b) { return integer(b ? 1 : 0); }
  RecordWriter& text(const std::string& s) {
    integer(static_cast<std::int64_t>(s.size()));
    bytes_.append(s);
    return *this;
  }
  RecordWriter& numbers(const std::vector<double>& xs) {
    integer(static_cast<std::int64_t>(xs.size()));
    for (double x : xs) number(x);
    return *this;
  }
  RecordWriter& texts(const std::vector<std::string>& list) {
    integer(static_cast<std::int64_t>(list.size()));
    for (const std::string& s : list) text(s);
    return *this;
  }
  const std::string& bytes() const { return bytes_; }

 private:
  RecordWriter& raw(const void* data, std::size_t size) {
    bytes_.append(static_cast<const char*>(data), size);
    return *this;
  }
  std::string bytes_;
};

// Reads back, in the order written. Throws std::runtime_error past the end (a record cut short).
class RecordReader {
 public:
  explicit RecordReader(const std::string& bytes) : bytes_(bytes) {}
  double number() { return raw<double>(); }
  std::int64_t integer() { return raw<std::int64_t>(); }
  bool flag() { return integer() != 0; }
  std::string text() {
    const std::size_t size = count();
    need(size);
    std::string s = bytes_.substr(position_, size);
    position_ += size;
    return s;
  }
  std::vector<double> numbers() {
    std::vector<double> xs(count());
    for (double& x : xs) x = number();
    return xs;
  }
  std::vector<std::string> texts() {
    std::vector<std::string> list(count());
    for (std::string& s : list) s = text();
    return list;
  }

 private:
  template <typename T>
  T raw() {
    need(sizeof(T));
    T value;
    std::memcpy(&value, bytes_.data() + position_, sizeof(T));
    position_ += sizeof(T);
    return value;
  }
  std::size_t count() {
    const std::int64_t n = integer();
    if (n < 0) throw std::runtime_error("a case record holds a negative length");
    return static_cast<std::size_t>(n);
  }
  void need(std::size_t size) const {
    if (position_ + size > bytes_.size()) throw std::runtime_error("a case record is cut short");
  }
  const std::string& bytes_;
  std::size_t position_ = 0;
};

}  // namespace csim
