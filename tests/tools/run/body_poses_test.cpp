// DIR/bodies.csv (output.bodies, tools/output/body_poses.h) against closed forms: a 3D rigid body
// spinning about a principal axis while it drifts (x = x0 + v t, the quaternion of the angle ω t about z)
// and a point falling from rest (z = z0 − ½ g t², which Moreau–Jean θ = ½ gives exactly under constant
// gravity); a fixed body has no row, and without the key there is no file.
#include "tools/run/run.h"
#include "tools/scene/scene.h"
#include "tests/tools/scene/scene_file_test.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace csim {
namespace {

const char* kScene = R"(dimension: 3
gravity: [0, 0, -9.81]
bodies:
  top:
    type: rigid
    mass: 2
    inertia: [0.1, 0.2, 0.3]
    position: [1, 2, 3]
    velocity: [0.5, 0, 9.81]
    angular_velocity: [0, 0, 2]
  grain: {type: point, mass: 1, position: [0, 0, 5]}
  ground: {type: fixed, shapes: {top: {type: halfspace, normal: [0, 0, 1]}}}
time: {end: 1, step: 0.001}
output: {rate: 0.25, paraview: none, bodies: true}
)";

std::vector<std::vector<std::string>> read_csv(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> fields;
    std::stringstream fields_of(line);
    for (std::string field; std::getline(fields_of, field, ',');) fields.push_back(field);
    rows.push_back(fields);
  }
  return rows;
}

class BodyPosesTest : public SceneFileTest {};

TEST_F(BodyPosesTest, PosesOfTheMovingBodiesAtEveryOutputRow) {
  const auto dir = std::filesystem::temp_directory_path() / "csim_body_poses_test";
  RunOptions options;
  options.output_directory = dir.string();
  run_scene(*load_scene(write(kScene), {}), options);
  const auto rows = read_csv(dir / "bodies.csv");
  ASSERT_EQ(rows.size(), 1u + 5u * 2u);  // header, then t = 0, 0.25, ..., 1 for top and grain
  EXPECT_EQ(rows[0], (std::vector<std::string>{"t", "body", "x", "y", "z", "qw", "qx", "qy", "qz"}));
  const double g = 9.81, omega = 2.0;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    ASSERT_EQ(rows[r].size(), 9u);
    const double t = std::stod(rows[r][0]);
    EXPECT_NEAR(t, 0.25 * static_cast<double>((r - 1) / 2), 1e-12);
    std::vector<double> x;
    for (std::size_t c = 2; c < 9; ++c) x.push_back(std::stod(rows[r][c]));
    if (rows[r][1] == "top") {  // thrown up at 9.81 m/s: z = 3 + 9.81 t − ½ g t²
      EXPECT_NEAR(x[0], 1.0 + 0.5 * t, 1e-12);
      EXPECT_NEAR(x[1], 2.0, 1e-12);
      EXPECT_NEAR(x[2], 3.0 + 9.81 * t - 0.5 * g * t * t, 1e-9);
      const double sign = x[3] >= 0.0 ? 1.0 : -1.0;  // q and −q are one rotation
      EXPECT_NEAR(sign * x[3], std::cos(0.5 * omega * t), 1e-12);
      EXPECT_NEAR(sign * x[6], std::sin(0.5 * omega * t), 1e-12);
      EXPECT_NEAR(x[4], 0.0, 1e-12);
      EXPECT_NEAR(x[5], 0.0, 1e-12);
    } else {
      ASSERT_EQ(rows[r][1], "grain");
      EXPECT_NEAR(x[0], 0.0, 1e-15);
      EXPECT_NEAR(x[2], 5.0 - 0.5 * g * t * t, 1e-9);
      EXPECT_EQ(x[3], 1.0);  // a point's orientation: the identity
    }
  }
  std::filesystem::remove_all(dir);
}

TEST_F(BodyPosesTest, NoFileWithoutTheKey) {
  const auto dir = std::filesystem::temp_directory_path() / "csim_body_poses_off_test";
  std::string text = kScene;
  text.replace(text.find(", bodies: true"), 14, "");
  RunOptions options;
  options.output_directory = dir.string();
  run_scene(*load_scene(write(text), {}), options);
  EXPECT_TRUE(std::filesystem::exists(dir / "probes.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir / "bodies.csv"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace csim
