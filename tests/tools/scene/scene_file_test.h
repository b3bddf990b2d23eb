// Scene texts written to temporary files for the tests that load them: one file per write, named
// after the test, removed when the test ends.
#pragma once

#include "tools/scene/scene.h"
#include "tools/scene/scene_error.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace csim {

class SceneFileTest : public ::testing::Test {
 protected:
  std::string write(const std::string& text) {
    const auto path = std::filesystem::temp_directory_path() /
                      ("csim_scene_" + std::to_string(files_.size()) + "_" +
                       ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".yaml");
    std::ofstream(path) << text;
    files_.push_back(path);
    return path.string();
  }
  // Loads a scene file and returns the SceneError's message ("" if it loaded).
  static std::string error_of(const std::string& file, const std::vector<std::string>& overrides = {}) {
    try {
      load_scene(file, overrides);
    } catch (const SceneError& e) {
      return e.what();
    }
    return "";
  }
  void TearDown() override {
    for (const auto& f : files_) std::filesystem::remove(f);
  }

 private:
  std::vector<std::filesystem::path> files_;
};

}  // namespace csim
