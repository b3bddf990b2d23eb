// A minimal JSON writer for the run summary (objects, arrays, numbers, strings, booleans), with
// indentation so that the file reads well in a diff. Non-finite numbers are written as null.
#pragma once

#include "engine/steppers/summary_entries.h"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

namespace csim {

class JsonWriter {
 public:
  JsonWriter& begin_object(const std::string& key = "") { open(key, '{'); return *this; }
  JsonWriter& end_object() { close('}'); return *this; }
  JsonWriter& begin_array(const std::string& key = "") { open(key, '['); return *this; }
  JsonWriter& end_array() { close(']'); return *this; }

  JsonWriter& value(const std::string& key, double number) {
    prefix(key);
    if (std::isfinite(number)) out_ << std::setprecision(17) << number;
    else out_ << "null";
    return *this;
  }
  JsonWriter& value(const std::string& key, long number) { prefix(key); out_ << number; return *this; }
  JsonWriter& value(const std::string& key, int number) { return value(key, static_cast<long>(number)); }
  JsonWriter& value(const std::string& key, bool flag) { prefix(key); out_ << (flag ? "true" : "false"); return *this; }
  JsonWriter& value(const std::string& key, const std::string& text) { prefix(key); quote(text); return *this; }
  JsonWriter& value(const std::string& key, const char* text) { return value(key, std::string(text)); }

  // A stepper's summary entries (summary_entries.h), at the current level.
  JsonWriter& entries(const SummaryEntries& entries) {
    for (const SummaryEntry& e : entries.entries()) {
      switch (e.kind) {
        case SummaryEntry::Kind::real: value(e.key, e.real); break;
        case SummaryEntry::Kind::integer: value(e.key, e.integer); break;
        case SummaryEntry::Kind::flag: value(e.key, e.flag); break;
        case SummaryEntry::Kind::text: value(e.key, e.text); break;
        case SummaryEntry::Kind::begin_group: begin_object(e.key); break;
        case SummaryEntry::Kind::end_group: end_object(); break;
      }
    }
    return *this;
  }

  std::string str() const { return out_.str() + "\n"; }

 private:
  void open(const std::string& key, char bracket) {
    prefix(key);
    out_ << bracket;
    first_.push_back(true);
  }
  void close(char bracket) {
    const bool empty = first_.back();
    first_.pop_back();
    if (!empty) newline();
    out_ << bracket;
  }
  void prefix(const std::string& key) {
    if (!first_.empty()) {
      if (!first_.back()) out_ << ",";
      first_.back() = false;
      newline();
    }
    if (!key.empty()) { quote(key); out_ << ": "; }
  }
  void newline() { out_ << "\n" << std::string(2 * first_.size(), ' '); }
  void quote(const std::string& text) {
    out_ << '"';
    for (char c : text) {
      if (c == '"' || c == '\\') out_ << '\\' << c;
      else if (c == '\n') out_ << "\\n";
      else if (static_cast<unsigned char>(c) < 0x20) out_ << "\\u" << std::hex << std::setw(4) << std::setfill('0') << int(c) << std::dec << std::setfill(' ');
      else out_ << c;
    }
    out_ << '"';
  }

  std::ostringstream out_;
  std::vector<bool> first_;
};

}  // namespace csim
