// Errors in a scene file: one line naming the file, the line and the key path, e.g.
//   scenes/incline/scene.yaml:12: bodies.block.mass: must be > 0 (got -1)
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace csim {

struct SceneError : std::runtime_error {
  SceneError(const std::string& file, int line, const std::string& path, const std::string& message)
      : std::runtime_error(format(file, line, path, message)) {}

  static std::string format(const std::string& file, int line, const std::string& path,
                            const std::string& message) {
    std::ostringstream text;  // (not operator+: GCC 12 warns falsely on it, -Wrestrict)
    text << file;
    if (line > 0) text << ':' << line;
    text << ": ";
    if (!path.empty()) text << path << ": ";
    text << message;
    return text.str();
  }
};

}  // namespace csim
