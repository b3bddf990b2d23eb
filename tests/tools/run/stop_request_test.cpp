#include "tools/run/stop_request.h"

#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>

namespace csim {
namespace {

namespace fs = std::filesystem;

const std::string kBar = CSIM_SOURCE_DIR "/scenes/fe-free-vibration/scene.yaml";

TEST(StopRequest, RunStopsAtAStepBoundaryAndLeavesNoFrames) {
  const fs::path dir = fs::path(::testing::TempDir()) / "csim_stop_request";
  fs::remove_all(dir);
  const auto scene = load_scene(kBar, {"time.end=1e-4"});
  request_stop(SIGTERM);
  try {
    run_scene(*scene, {dir.string()});
    ADD_FAILURE() << "the run went to its end";
  } catch (const StopRequested& stop) {
    EXPECT_EQ(stop.signal, SIGTERM);
  }
  clear_stop_request();
  EXPECT_FALSE(fs::exists(dir / "paraview"));
  EXPECT_FALSE(fs::exists(dir / "summary.json"));
  EXPECT_NO_THROW(run_scene(*scene, {}));  // forgotten: the next run goes to its end
}

}  // namespace
}  // namespace csim
