// ProbeEvaluator on its own: each kind of probe on a small World and a State set by hand, against the
// values of probes.h's definitions computed by hand.
#include "tools/run/probes.h"
#include "tests/engine/test_worlds.h"
#include "engine/state.h"
#include "engine/world.h"
#include "tools/scene/scene.h"
#include "tools/run/checks.h"
#include "tools/run/run.h"

#include <gtest/gtest.h>

namespace csim {
namespace {

// Two point masses in the plane: "ball" (2 kg, reference (1, 2) m) resting on "floor" (a second
// mass at the origin), with one contact law between [ball, floor].
World ball_on_floor() {
  World world;
  world.dimension = 2;
  world.bodies.push_back(test::point_mass("ball", 2, 2.0, {1.0, 2.0, 0.0}));
  world.bodies.push_back(test::point_mass("floor", 2, 5.0, {0.0, 0.0, 0.0}));
  ContactLaw law;
  law.body_a = 0;
  law.body_b = 1;
  world.contact_laws.push_back(law);
  world.finalize_layout();
  return world;
}

ProbeDefinition probe(ProbeDefinition::Kind kind) {
  ProbeDefinition p;
  p.kind = kind;
  return p;
}

TEST(ProbeEvaluator, EachKindAgainstHandValues) {
  const World world = ball_on_floor();
  RunSettings run;
  run.step = 0.01;  // s: contact forces are impulses / h
  using Kind = ProbeDefinition::Kind;
  ProbeDefinition p = probe(Kind::displacement);  // x displacement of the ball, scaled by 2
  p.body = 0;
  p.scale = 2.0;
  run.probes.push_back(p);
  p = probe(Kind::position);  // y position of the ball
  p.body = 0;
  p.direction = Eigen::Vector3d::UnitY();
  run.probes.push_back(p);
  p = probe(Kind::velocity);  // v_y of the ball
  p.velocity_index = 1;
  run.probes.push_back(p);
  for (const char* term : {"kinetic", "mechanical", "work"}) {
    p = probe(Kind::energy);
    p.energy_term = term;
    run.probes.push_back(p);
  }
  for (const char* component : {"normal", "tangential", "y"}) {
    p = probe(Kind::contact_force);
    p.contact_law = 0;
    p.force_component = component;
    run.probes.push_back(p);
  }
  p = probe(Kind::contact_count);
  p.contact_law = 0;
  p.force_component = "closed";
  run.probes.push_back(p);

  State state;
  state.t = 0.5;
  state.q = Eigen::Vector4d(1.5, 2.5, 0.0, 0.0);
  state.v = Eigen::Vector4d(0.0, -3.0, 0.0, 0.0);
  state.energy.kinetic = 4.0;  // J
  state.energy.elastic = 1.0;
  state.energy.work_of_loads = 7.0;
  // One contact: the point's body A is the floor, B the ball (the law's first body), n from A to B
  // = +y, t1 = e_z × n = −x; impulse (r_n, r_t1) = (0.02, 0.005) N·s over h = 0.01 s: a force of
  // 2 N along +y and 0.5 N along t1 on the ball.
  ActiveContact c;
  c.law = 0;
  c.body_a = 1;
  c.body_b = 0;
  c.point.normal = Eigen::Vector3d::UnitY();
  complete_frame(c.point, true);
  ASSERT_NEAR(c.point.t1.x(), -1.0, 1e-15);
  c.impulse = Eigen::Vector3d(0.02, 0.005, 0.0);
  state.contacts.push_back(c);

  const ProbeEvaluator probes(world, run);
  std::vector<double> values;
  probes.evaluate(state, values);
  ASSERT_EQ(values.size(), run.probes.size());
  EXPECT_DOUBLE_EQ(values[0], 2.0 * 0.5);  // displacement 0.5 m, scale 2
  EXPECT_DOUBLE_EQ(values[1], 2.5);        // position y
  EXPECT_DOUBLE_EQ(values[2], -3.0);       // velocity
  EXPECT_DOUBLE_EQ(values[3], 4.0);        // kinetic
  EXPECT_DOUBLE_EQ(values[4], 5.0);        // mechanical = kinetic + elastic
  EXPECT_DOUBLE_EQ(values[5], 7.0);        // work of loads
  EXPECT_NEAR(values[6], 2.0, 1e-12);      // normal force (compressive positive)
  EXPECT_NEAR(values[7], 0.5, 1e-12);      // tangential: along e_z × n, n into the ball
  EXPECT_NEAR(values[8], 2.0, 1e-12);      // y component of the resultant on the ball
  EXPECT_EQ(values[9], 1.0);               // one closed point

  // An open contact (no normal impulse) is not counted and carries no force.
  state.contacts[0].impulse.setZero();
  probes.evaluate(state, values);
  EXPECT_EQ(values[9], 0.0);
  EXPECT_EQ(values[6], 0.0);
}

// A run evaluates between its output rows only the probes whose every sample a check reads
// (CheckEvaluator::sampled_probes: extrema, values at a time, means); the others serve final checks
// and rows alone. The checks and the rows must be those of a run that samples every probe at every
// step (an output row at every step): on the incline (final checks only), on SDNV104 (extrema and
// times of dx; the forces and the balance read by no check) and on SDND100 (dy at given times, dx
// final).
TEST(ProbeEvaluator, ProbesThatNoCheckSamplesAreReadAtRowsAndTheEndAlone) {
  for (const char* name : {"incline-3d", "sdnv104-rigid", "sdnd100-a"}) {
    const std::string file = std::string(CSIM_SOURCE_DIR "/scenes/") + name + "/scene.yaml";
    const auto sparse = load_scene(file, {"time.end=2", "time.step=2e-3", "output.rate=0.5"});
    const auto dense = load_scene(file, {"time.end=2", "time.step=2e-3", "output.rate=2e-3"});
    const std::vector<int> sampled = CheckEvaluator(sparse->run, sparse->document.scope).sampled_probes();
    std::vector<int> expected;  // sdnv104's dx alone, sdnd100's dy alone
    for (std::size_t p = 0; p < sparse->run.probes.size(); ++p)
      if ((std::string(name) == "sdnv104-rigid" && sparse->run.probes[p].name == "dx") ||
          (std::string(name) == "sdnd100-a" && sparse->run.probes[p].name == "dy"))
        expected.push_back(static_cast<int>(p));
    EXPECT_EQ(sampled, expected) << name;
    const RunReport a = run_scene(*sparse, {}), b = run_scene(*dense, {});
    ASSERT_EQ(a.checks.size(), b.checks.size());
    int evaluated = 0;
    for (std::size_t c = 0; c < a.checks.size(); ++c) {
      EXPECT_EQ(a.checks[c].evaluated, b.checks[c].evaluated) << name << ", " << a.checks[c].name;
      if (a.checks[c].evaluated) {
        EXPECT_EQ(a.checks[c].value, b.checks[c].value) << name << ", " << a.checks[c].name;
      }
      evaluated += a.checks[c].evaluated;
    }
    // sdnv104: x1, t1 and the rest at least; sdnd100: dy at four times, twice, and dx at the end.
    EXPECT_GE(evaluated, std::string(name) == "sdnv104-rigid" ? 3 : std::string(name) == "sdnd100-a" ? 9 : 4) << name;
    ASSERT_EQ(a.sample_times.size(), 5u) << name;  // t = 0, 0.5, …, 2
    for (std::size_t i = 0; i < a.sample_times.size(); ++i) {
      std::size_t j = 0;
      while (j < b.sample_times.size() && std::abs(b.sample_times[j] - a.sample_times[i]) > 1e-9) ++j;
      ASSERT_LT(j, b.sample_times.size()) << name << ", row at " << a.sample_times[i];
      EXPECT_TRUE(a.samples[i] == b.samples[j]) << name << ", row at " << a.sample_times[i];
    }
  }
}

// evaluate with a list of probes sets those and leaves the others' entries as they were.
TEST(ProbeEvaluator, AMaskedEvaluationLeavesTheOtherEntries) {
  const World world = ball_on_floor();
  RunSettings run;
  run.step = 0.01;
  ProbeDefinition p;
  p.kind = ProbeDefinition::Kind::velocity;
  p.velocity_index = 1;
  run.probes.push_back(p);
  p.velocity_index = 0;
  run.probes.push_back(p);
  const ProbeEvaluator probes(world, run);
  State state;
  state.q = Vector::Zero(world.position_size);
  state.v = Vector::LinSpaced(world.velocity_size, 1.0, 4.0);
  std::vector<double> values = {-7.0, -8.0};
  probes.evaluate(state, values, std::vector<int>{1});
  EXPECT_EQ(values[0], -7.0);
  EXPECT_EQ(values[1], state.v(0));
  probes.evaluate(state, values, std::vector<int>{0});
  EXPECT_EQ(values[0], state.v(1));
}

}  // namespace
}  // namespace csim
