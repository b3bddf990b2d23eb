#include "tools/scene_argument.h"

#include <filesystem>
#include <system_error>

namespace csim::cli {

std::string scene_file(const std::string& scene) {
  std::error_code error;
  if (std::filesystem::is_directory(scene, error)) return (std::filesystem::path(scene) / "scene.yaml").string();
  return scene;
}

}  // namespace csim::cli
