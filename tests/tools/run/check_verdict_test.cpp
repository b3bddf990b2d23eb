// What a run may claim about its checks (checks.h, README "exit status"): excluded and not-evaluated
// checks are never passes, a run passes only when some check was evaluated and none failed, and
// parameters for which a check has no reference, window or probe scale still run to the end.
#include "tools/run/run.h"
#include "tools/scene/scene.h"
#include "tools/scene/scene_error.h"
#include "tests/tools/scene/scene_file_test.h"

#include <gtest/gtest.h>

#include <cmath>

namespace csim {
namespace {

// A block resting on the ground: x stays 0, so `still` passes whenever it is evaluated. CHECKS is
// replaced by each test's checks.
const char* kScene = R"(dimension: 2
parameters:
  mass: 2
  speed: 1
  start: 0.02
gravity: [0, -9.81]
bodies:
  block:
    type: rigid
    mass: =mass
    position: [0, 0.5]
    shapes:
      cube: {type: box, size: [1, 1]}
  ground:
    type: fixed
    shapes:
      top: {type: halfspace, normal: [0, 1]}
contacts:
  block_on_ground: {between: [block, ground], mu: 0.5}
time: {end: 0.1, step: 0.01}
probes:
  x: {displacement: {body: block, component: x}}
  y_per_speed: {displacement: {body: block, component: y, scale: =1/speed}}
checks:
CHECKS)";

class CheckVerdict : public SceneFileTest {
 protected:
  std::unique_ptr<Scene> load(const std::string& checks, const std::vector<std::string>& overrides = {}) {
    std::string text = kScene;
    text.replace(text.find("CHECKS"), 6, checks);
    return load_scene(write(text), overrides);
  }
};

const char* kStill =
    "  still: {probe: x, final: true, reference: 0, tolerance: {absolute: 1e-12}, kind: analytical, source: test}\n";

TEST_F(CheckVerdict, AnEvaluatedPassingCheckPasses) {
  const RunReport report = run_scene(*load(kStill), {});
  const CheckCounts n = report.counts();
  EXPECT_EQ(n.passed, 1);
  EXPECT_TRUE(report.passed());
}

// An excluded check (only_if false) used to count as passed with the value 0: a run whose only check
// was excluded said "all checks passed".
TEST_F(CheckVerdict, AnExcludedCheckIsNeverAPass) {
  const auto scene = load(
      "  heavy_only: {probe: x, final: true, reference: 0, tolerance: {absolute: 1e-12}, kind: analytical,"
      " source: test, only_if: =mass > 5}\n");
  const RunReport report = run_scene(*scene, {});
  ASSERT_EQ(report.checks.size(), 1u);
  const CheckResult& c = report.checks[0];
  EXPECT_TRUE(c.skipped);
  EXPECT_FALSE(c.passed);
  EXPECT_FALSE(c.evaluated);
  EXPECT_TRUE(std::isnan(c.value));
  EXPECT_NE(c.note.find("is false for these parameters"), std::string::npos) << c.note;
  EXPECT_EQ(report.counts().excluded, 1);
  EXPECT_FALSE(report.passed());
  EXPECT_FALSE(report.plain_simulation());  // it was meant to be judged: exit 1, not a plain simulation
  EXPECT_FALSE(CheckCounts{}.pass());  // no checks at all: not judged, not a pass
}

// A scene that declares no check is a plain simulation: not a pass (nothing was judged), but a run to
// its end that `csim run` ends with exit 0; a numerical failure is never one.
TEST_F(CheckVerdict, ASceneWithoutChecksIsAPlainSimulation) {
  RunReport report = run_scene(*load(""), {});
  EXPECT_TRUE(report.checks.empty());
  EXPECT_FALSE(report.passed());
  EXPECT_TRUE(report.plain_simulation());
  EXPECT_NEAR(report.state.t, 0.1, 1e-12);
  report.failure = RunFailure{};
  EXPECT_FALSE(report.plain_simulation());
}

// A check whose time lies beyond the run's end is reported, with its reason, and spoils the pass even
// when another check passed.
TEST_F(CheckVerdict, ACheckBeyondTheWindowIsNotEvaluatedAndSpoilsThePass) {
  const auto scene = load(std::string(kStill) +
      "  later: {probe: x, at: 5, reference: 0, tolerance: {absolute: 1e-12}, kind: analytical, source: test}\n");
  const RunReport report = run_scene(*scene, {});
  const CheckCounts n = report.counts();
  EXPECT_EQ(n.passed, 1);
  EXPECT_EQ(n.not_evaluated, 1);
  EXPECT_NE(report.checks[1].note.find("beyond the run's end"), std::string::npos) << report.checks[1].note;
  EXPECT_FALSE(report.passed());
}

// Parameters can make a window empty or a time negative: the check is not evaluated, the scene still
// loads and runs. Written as numbers, the same window is a mistake in the file.
TEST_F(CheckVerdict, AWindowEmptyForTheseParametersIsNotEvaluated) {
  const std::string mean =
      "  settled: {probe: x, mean: [=start, 0.05], reference: 0, tolerance: {absolute: 1e-12}, kind: analytical, source: test}\n"
      "  early: {probe: x, at: =0.05 - start, reference: 0, tolerance: {absolute: 1e-12}, kind: analytical, source: test}\n";
  const RunReport report = run_scene(*load(mean, {"parameters.start=0.08"}), {});
  ASSERT_EQ(report.checks.size(), 2u);
  for (const CheckResult& c : report.checks) {
    EXPECT_FALSE(c.evaluated) << c.name;
    EXPECT_FALSE(c.skipped) << c.name;
    EXPECT_NE(c.note.find("for these parameters"), std::string::npos) << c.note;
  }
  EXPECT_EQ(run_scene(*load(mean), {}).counts().passed, 2);  // start = 0.02: both judged
  EXPECT_THROW(load("  bad: {probe: x, mean: [0.08, 0.05], reference: 0, tolerance: {absolute: 1}, kind: analytical, source: test}\n"),
               SceneError);
}

// A probe normalized by a parameter that is 0 has no value: its checks are not evaluated and its
// column holds NaN, instead of the scene being refused as bad input.
TEST_F(CheckVerdict, AProbeWhoseScaleIsNotFiniteHasNoValueAndItsChecksAreNotEvaluated) {
  const std::string checks =
      std::string(kStill) +
      "  height: {probe: y_per_speed, final: true, reference: 0, tolerance: {absolute: 1e-9}, kind: analytical, source: test}\n";
  const RunReport report = run_scene(*load(checks, {"parameters.speed=0"}), {});
  const CheckCounts n = report.counts();
  EXPECT_EQ(n.passed, 1);
  EXPECT_EQ(n.not_evaluated, 1);
  EXPECT_NE(report.checks[1].note.find("probe 'y_per_speed' has no value"), std::string::npos) << report.checks[1].note;
  EXPECT_TRUE(std::isnan(report.samples.back()[1]));
  EXPECT_EQ(run_scene(*load(checks), {}).counts().passed, 2);  // speed = 1: judged
}

// SDNV104's analytical solution has no rest time when friction is 0 (the mass never stops): the `rest`
// check's only_if cannot be evaluated, counts as false, and the other checks run and pass. It used to
// be refused as bad input (exit 2).
TEST(CheckVerdictScenes, AnOnlyIfWithoutAnAnswerExcludesItsCheck) {
  const auto scene = load_scene(CSIM_SOURCE_DIR "/scenes/sdnv104-rigid/scene.yaml", {"parameters.mu=0"});
  const RunReport report = run_scene(*scene, {});
  const CheckCounts n = report.counts();
  EXPECT_EQ(n.failed, 0);
  EXPECT_EQ(n.not_evaluated, 0);
  EXPECT_GE(n.passed, 10);  // x1..x5, t1..t5 (x2, x4 are 0: judged by the absolute tolerance)
  bool rest_seen = false;
  for (const CheckResult& c : report.checks)
    if (c.name == "rest") {
      rest_seen = true;
      EXPECT_TRUE(c.skipped);
      EXPECT_NE(c.note.find("could not be evaluated, counted as false"), std::string::npos) << c.note;
      EXPECT_NE(c.note.find("still moving"), std::string::npos) << c.note;
    }
  EXPECT_TRUE(rest_seen);
  EXPECT_TRUE(report.passed());
}

// A step that does not divide the window is shortened so that the last step lands on time.end; a step
// count beyond 2^53 is refused at load.
TEST_F(CheckVerdict, TheLastStepLandsOnTheEndTime) {
  const auto scene = load(kStill, {"time.step=0.03"});
  EXPECT_EQ(scene->run.steps, 4);
  EXPECT_DOUBLE_EQ(scene->run.step, 0.025);
  EXPECT_DOUBLE_EQ(scene->run.requested_step, 0.03);
  const RunReport report = run_scene(*scene, {});
  EXPECT_NEAR(report.state.t, 0.1, 1e-15);
  EXPECT_NEAR(report.sample_times.back(), 0.1, 1e-15);
  EXPECT_EQ(load(kStill)->run.step, 0.01);  // a step that divides the window is kept as written
  try {
    load(kStill, {"time.step=1e-300"});
    ADD_FAILURE() << "1e-300 accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("time.step: time.end / time.step = 1e+299 steps, more than 2^53"),
              std::string::npos) << e.what();
  }
}

// A bouncing ball (Newton's law, e = 0.55, h0 = 1 m), every step a row of probes.csv. The velocity jumps
// at each impact and the height turns at a kink there: their extrema are values the run produced, the
// recorded ones, never a parabola through the jump (which read −5.26 m/s for an impact at −4.43 m/s, and
// a height below the floor). The apex, a smooth turning point, keeps its parabola: it lies above the
// highest sample (e = 0.55 puts it between two samples), near e² h0 (within the step's error on the
// impact, 1 % at this coarse step).
TEST_F(CheckVerdict, AnExtremumAcrossAnImpactIsARecordedValue) {
  const std::string scene_text = R"(dimension: 2
gravity: [0, -9.81]
bodies:
  ball:
    type: point
    mass: 1
    position: [0, 1.1]
    shapes:
      disk: {type: sphere, radius: 0.1}
  floor:
    type: fixed
    shapes:
      surface: {type: halfspace, normal: [0, 1], offset: 0}
contacts:
  ball_on_floor: {between: [ball, floor], restitution: 0.55}
time: {end: 0.84, step: 7e-4}
integrator: {type: moreau-jean, theta: 0.5}
output: {rate: 7e-4}
probes:
  height: {position: {body: ball, point: [0, -0.1], component: y}}
  vy: {velocity: {body: ball, component: y}}
checks:
  v_impact: {probe: vy, minimum: 1, reference: -4.4294469, tolerance: {relative: 1e-2}, kind: analytical, source: test}
  v_rebound: {probe: vy, maximum: 1, reference: 2.4361958, tolerance: {relative: 1e-2}, kind: analytical, source: test}
  lowest: {probe: height, minimum: 1, reference: 0, tolerance: {absolute: 1e-2}, kind: analytical, source: test}
  apex: {probe: height, maximum: 1, reference: 0.3025, tolerance: {relative: 2e-2}, kind: analytical, source: test}
)";
  const RunReport report = run_scene(*load_scene(write(scene_text), {}), {});
  ASSERT_EQ(report.sample_times.size(), 1201u);
  double v_min = INFINITY, v_max = -INFINITY, lowest = INFINITY, highest_after_bounce = -INFINITY;
  for (std::size_t k = 0; k < report.samples.size(); ++k) {
    const double height = report.samples[k][0], vy = report.samples[k][1];
    v_min = std::min(v_min, vy);
    lowest = std::min(lowest, height);
    if (report.sample_times[k] > 0.55) highest_after_bounce = std::max(highest_after_bounce, height);
    if (report.sample_times[k] < 0.6) v_max = std::max(v_max, vy);  // up to the apex
  }
  ASSERT_EQ(report.checks.size(), 4u);
  for (const CheckResult& c : report.checks) {
    EXPECT_TRUE(c.passed) << c.name << ": " << c.value;
    if (c.name == "v_impact") {
      EXPECT_EQ(c.value, v_min);
    }
    if (c.name == "v_rebound") {
      EXPECT_EQ(c.value, v_max);
    }
    if (c.name == "lowest") {
      EXPECT_EQ(c.value, lowest);
    }
    if (c.name == "apex") {
      EXPECT_GT(c.value, highest_after_bounce);
      EXPECT_NEAR(c.value, 0.3025, 0.3025 * 2e-2);
    }
  }

  // Values at a time interpolate the samples since the jump only: between the first two samples after
  // the impact, their line (the velocity is linear there); inside the step of the impact, the sample
  // past the time, the value after the jump.
  std::size_t k = 1;
  while (report.samples[k][1] <= 0.0) ++k;  // the first sample after the impact
  const double h = 7e-4, t_k = report.sample_times[k];
  const double after = 0.5 * (report.samples[k][1] + report.samples[k + 1][1]), jump_step = report.samples[k][1];
  char checks[512];
  std::snprintf(checks, sizeof checks,
                "  v_after: {probe: vy, at: %.17g, reference: %.17g, tolerance: {absolute: 1e-12}, kind: analytical, "
                "source: test}\n"
                "  v_jump: {probe: vy, at: %.17g, reference: %.17g, tolerance: {absolute: 1e-12}, kind: analytical, "
                "source: test}\n",
                t_k + 0.5 * h, after, t_k - 0.5 * h, jump_step);
  std::string with_at = scene_text;
  with_at.replace(with_at.find("  v_impact:"), 0, checks);
  const RunReport at_report = run_scene(*load_scene(write(with_at), {}), {});
  for (const CheckResult& c : at_report.checks)
    if (c.name == "v_after" || c.name == "v_jump") {
      EXPECT_TRUE(c.passed) << c.name << ": " << c.value << " vs " << c.reference;
    }
}

}  // namespace
}  // namespace csim
