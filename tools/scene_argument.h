// The SCENE argument of every command: a scene folder (holding scene.yaml) or a scene file.
#pragma once

#include <string>

namespace csim::cli {

// The scene file SCENE names: FOLDER/scene.yaml for a folder, else SCENE itself.
std::string scene_file(const std::string& scene);

}  // namespace csim::cli
