// Errors in a scene file: one line naming the file, the line and the key path, e.g.
//   scenes/incline/scene.yaml:12: bodies.block.mass: must be > 0 (got -1)
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace csim {

// The text with every byte that a terminal would act on, or that breaks the one-line message, written
// as \xNN: C0 controls (ESC, CR, LF, ...), DEL, C1 controls (U+0080 to U+009F; U+009B is a CSI to some
// terminals) and bytes that are not valid UTF-8. Valid UTF-8 (μ, θ) is kept as it is.
std::string printable_text(std::string_view text);

struct SceneError : std::runtime_error {
  SceneError(const std::string& file, int line, const std::string& path, const std::string& message)
      : std::runtime_error(format(file, line, path, message)) {}

  // Every part may echo the scene's own bytes (a key, a value, a file name), hence printable_text.
  static std::string format(const std::string& file, int line, const std::string& path,
                            const std::string& message) {
    std::ostringstream text;  // (not operator+: GCC 12 warns falsely on it, -Wrestrict)
    text << file;
    if (line > 0) text << ':' << line;
    text << ": ";
    if (!path.empty()) text << path << ": ";
    text << message;
    return printable_text(text.str());
  }
};

}  // namespace csim
