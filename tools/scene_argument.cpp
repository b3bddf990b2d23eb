#include "tools/scene_argument.h"

#include "tools/scene/scene_error.h"

#include <filesystem>
#include <system_error>

namespace csim::cli {

namespace {

namespace fs = std::filesystem;

bool is_scene(const fs::path& path) {
  std::error_code error;
  return fs::is_regular_file(fs::is_directory(path, error) ? path / "scene.yaml" : path, error);
}

// The scenes/ folder a bare name most likely meant: the current folder's, then the source tree's.
std::string suggestion(const fs::path& scene) {
  if (scene.is_absolute()) return "";
  if (is_scene(fs::path("scenes") / scene)) return (fs::path("scenes") / scene).string();
#ifdef CSIM_SOURCE_DIR
  const fs::path in_source_tree = fs::path(CSIM_SOURCE_DIR) / "scenes" / scene;
  if (is_scene(in_source_tree)) return in_source_tree.string();
#endif
  return "";
}

}  // namespace

std::string scene_file(const std::string& scene) {
  std::error_code error;
  if (fs::is_directory(scene, error)) return (fs::path(scene) / "scene.yaml").string();
  if (!scene.empty() && !fs::exists(scene, error)) {
    const std::string guess = suggestion(scene);
    throw SceneError(scene, 0, "", "cannot open the scene file: no such file or folder" +
                                       (guess.empty() ? std::string() : "; did you mean " + guess + "?"));
  }
  return scene;
}

}  // namespace csim::cli
