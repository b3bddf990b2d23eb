// The SCENE argument of every command: a scene folder (holding scene.yaml) or a scene file.
#pragma once

#include <string>

namespace csim::cli {

// The scene file SCENE names: FOLDER/scene.yaml for a folder, else SCENE itself. Throws SceneError when
// SCENE names nothing, suggesting scenes/SCENE (from the current folder, or from the source tree csim
// was built from) when that is a scene: `csim run sdnv104-rigid` is the usual slip.
std::string scene_file(const std::string& scene);

}  // namespace csim::cli
