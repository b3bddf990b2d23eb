// Text helpers shared by the CSV writers (work precision, stability).
#pragma once

#include <string>

namespace csim {

// The text on one line: line breaks become spaces, trailing spaces go.
inline std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

// RFC 4180: a field holding a comma or a quote is quoted, its quotes doubled (failure messages do).
inline std::string csv_field(const std::string& text) {
  const std::string line = one_line(text);
  if (line.find_first_of(",\"") == std::string::npos) return line;
  std::string quoted = "\"";
  for (char c : line) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace csim
