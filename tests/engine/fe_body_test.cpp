// Finite-element bodies in the engine: energy of the θ-method on free vibration (consistent and lumped
// mass), dissipation for θ > ½, and a static tension against the closed form.
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <gtest/gtest.h>

#include <fstream>

namespace csim {
namespace {

const std::string kBar = CSIM_SOURCE_DIR "/scenes/fe-free-vibration/scene.yaml";

TEST(FeBody, FreeVibrationConservesEnergyAtHalfTheta) {
  for (const char* mass : {"bodies.bar.mass=consistent", "bodies.bar.mass=lumped"}) {
    const auto scene = load_scene(kBar, {mass});
    const RunReport report = run_scene(*scene, {});
    const double initial = report.samples.front()[1];
    ASSERT_GT(initial, 0.0);
    for (const auto& row : report.samples) EXPECT_NEAR(row[1], initial, 1e-10 * initial) << mass;
  }
}

TEST(FeBody, FreeVibrationLosesEnergyAboveHalfTheta) {
  const auto scene = load_scene(kBar, {"parameters.theta=0.7"});
  const RunReport report = run_scene(*scene, {});
  double previous = report.samples.front()[1];
  for (const auto& row : report.samples) {
    EXPECT_LE(row[1], previous * (1.0 + 1e-14));
    previous = row[1];
  }
  EXPECT_LT(previous, 0.99 * report.samples.front()[1]);
  EXPECT_GT(report.state.energy.numerical_dissipation, 0.0);
  EXPECT_LE(report.state.energy.max_abs_residual, 1e-9 * report.samples.front()[1]);
}

TEST(FeBody, PressureOnAFreeEndGivesTheUniaxialDisplacement) {
  // The same bar pulled by a traction p on its right end, quasi-statically (heavily damped by θ = 1
  // and a long run): u_tip = p L / E (ν = 0).
  const std::string scene_text = R"(dimension: 2
bodies:
  bar:
    type: elastic
    mesh: {generator: rectangle, size: [1, 0.1], divisions: [10, 1]}
    material: {young: 1.0e6, poisson: 0, density: 1}
    fixed: {left: [x], bottom_left: [y]}
loads:
  pull: {body: bar, pressure: -1000, faces: right}
time: {end: 2, step: 0.01}
integrator: {theta: 1}
probes:
  tip: {displacement: {body: bar, point: [1, 0.1], component: x}}
checks:
  tip: {probe: tip, final: true, reference: 1e-3, tolerance: {relative: 1e-6}, kind: analytical, source: "p L / E"}
)";
  const std::string file = ::testing::TempDir() + "csim_fe_tension.yaml";
  { std::ofstream(file) << scene_text; }
  const auto scene = load_scene(file, {});
  const RunReport report = run_scene(*scene, {});
  EXPECT_TRUE(report.passed()) << report.checks[0].value;
}

}  // namespace
}  // namespace csim
