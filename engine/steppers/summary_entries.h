// A stepper's part of the run summary (DESIGN.md §4: summary.json), as plain ordered entries: the
// stepper names its settings and statistics, tools/output writes them (as JSON), so that the core
// knows no file format and the summary no stepper.
#pragma once

#include "engine/state.h"

#include <string>
#include <vector>

namespace csim {

struct SummaryEntry {
  enum class Kind { real, integer, flag, text, begin_group, end_group };
  Kind kind = Kind::real;
  std::string key;        // empty for end_group
  double real = 0.0;
  long integer = 0;
  bool flag = false;
  std::string text;
};

// Entries in the order they are added; groups nest (begin_group ... end_group).
class SummaryEntries {
 public:
  SummaryEntries& add(const std::string& key, double value) {
    push(SummaryEntry::Kind::real, key).real = value;
    return *this;
  }
  SummaryEntries& add(const std::string& key, long value) {
    push(SummaryEntry::Kind::integer, key).integer = value;
    return *this;
  }
  SummaryEntries& add(const std::string& key, int value) { return add(key, static_cast<long>(value)); }
  SummaryEntries& add(const std::string& key, bool value) {
    push(SummaryEntry::Kind::flag, key).flag = value;
    return *this;
  }
  SummaryEntries& add(const std::string& key, const std::string& value) {
    push(SummaryEntry::Kind::text, key).text = value;
    return *this;
  }
  SummaryEntries& add(const std::string& key, const char* value) { return add(key, std::string(value)); }
  SummaryEntries& begin_group(const std::string& key) {
    push(SummaryEntry::Kind::begin_group, key);
    return *this;
  }
  SummaryEntries& end_group() {
    push(SummaryEntry::Kind::end_group, "");
    return *this;
  }

  const std::vector<SummaryEntry>& entries() const { return entries_; }
  bool empty() const { return entries_.empty(); }

 private:
  SummaryEntry& push(SummaryEntry::Kind kind, const std::string& key) {
    SummaryEntry& entry = entries_.emplace_back();
    entry.kind = kind;
    entry.key = key;
    return entry;
  }
  std::vector<SummaryEntry> entries_;
};

// The Newton iterations' group ("newton") of the steppers that iterate (quasi-static; Moreau–Jean with
// finite-strain bodies): tolerance as the stepper reads it (dimensionless), counters from the state.
void add_newton_group(const SolverCounters& counters, double tolerance, SummaryEntries& out);

}  // namespace csim
