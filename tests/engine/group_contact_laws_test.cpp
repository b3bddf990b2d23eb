// Contact laws by group (engine/contact_stage/contact_law_table.h) in a run: a pile declared with one
// group law meets the same contacts and moves the same as the pile with every touching pair declared
// by hand (bench/pile_scene.h); a law naming a body overrides the group's law with its own μ; a body
// that no law holds passes through the others.
#include "bench/pile_scene.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <unistd.h>

namespace csim {
namespace {

struct SceneRun {
  std::unique_ptr<Scene> scene;
  RunReport report;
};

SceneRun run_text(const std::string& text, const std::string& name) {
  const std::string file = ::testing::TempDir() + "group_laws_" + name + "_" + std::to_string(getpid()) + ".yaml";
  std::ofstream(file) << text;
  SceneRun run;
  run.scene = load_scene(file, {});
  std::remove(file.c_str());
  run.report = run_scene(*run.scene, {});
  return run;
}

// The 29-sphere pile of a 4 × 4 base (16 + 9 + 4), radius 0.1 m, 10 steps of 1 ms, μ 0.5: its 92
// sphere–sphere neighbour pairs and 29 floor laws, or two laws ([floor, spheres] and [spheres, spheres],
// 406 sphere pairs). 124 contacts touch: the 92 pairs, 16 spheres on the floor, 16 against the walls. The pairs that are not neighbours are 0.08 m apart or more, beyond any margin, so
// the contacts are the same; their order too (contacts sort by collision object, the same objects), so
// each step solves the same problem and the runs agree to round-off.
TEST(GroupContactLaws, APileByGroupMovesAsThePileDeclaredPairByPair) {
  const int steps = 10;
  const std::vector<bench::Sphere> spheres = bench::pile(29, 4, 4, 0.1);
  const SceneRun by_pairs = run_text(bench::scene_text(spheres, 0.1, steps, 4, 4, 0.5, 20000), "pairs");
  const SceneRun by_group = run_text(
      bench::scene_text(spheres, 0.1, steps, 4, 4, 0.5, 20000, bench::Declaration::group), "group");
  ASSERT_EQ(by_group.scene->world.contact_laws.size(), 2u);
  ASSERT_EQ(by_pairs.scene->world.contact_laws.size(), 29u + 92u);
  const State &p = by_pairs.report.state, &g = by_group.report.state;
  EXPECT_EQ(p.counters.not_converged + g.counters.not_converged, 0);
  ASSERT_EQ(p.contacts.size(), g.contacts.size());
  EXPECT_EQ(g.contacts.size(), 124u);
  const World& world = by_group.scene->world;
  for (std::size_t k = 0; k < g.contacts.size(); ++k) {
    ASSERT_TRUE(p.contacts[k].point.key == g.contacts[k].point.key) << "contact " << k;
    EXPECT_EQ(p.contacts[k].body_a, g.contacts[k].body_a);
    EXPECT_EQ(p.contacts[k].body_b, g.contacts[k].body_b);
    // A floor contact takes the law [floor, spheres], two spheres [spheres, spheres].
    const bool on_floor = world.bodies[g.contacts[k].body_a].name == "floor" ||
                          world.bodies[g.contacts[k].body_b].name == "floor";
    EXPECT_EQ(world.contact_laws[g.contacts[k].law].name, on_floor ? "floor" : "pile");
    // Impulses about m g h = 1e-2 N·s: round-off is 1e-17.
    EXPECT_LE((p.contacts[k].impulse - g.contacts[k].impulse).norm(), 1e-14) << "contact " << k;
  }
  EXPECT_LE((p.q - g.q).lpNorm<Eigen::Infinity>(), 1e-14);
  EXPECT_LE((p.v - g.v).lpNorm<Eigen::Infinity>(), 1e-14);
}

// Three spheres of 1 kg, radius 0.1 m, on the floor, 1 m apart, gravity tilted (g_t = 2 m/s² along x,
// g_z = 9.81 m/s²), 0.1 s. a and b are in the group balls, whose law with the floor has μ = 0.5, but a
// law [floor, a] gives a μ = 0.05. A sphere rolls without slipping while g_t ≤ 3.5 μ g_z (17.2 for
// μ 0.5), its centre then accelerating at (5/7) g_t; it slips beyond (1.72 for μ 0.05), accelerating
// at g_t − μ g_z. c is in no law: it falls through the floor, z = 0.1 − ½ g_z t².
std::string override_scene() {
  return "dimension: 3\n"
         "gravity: [2, 0, -9.81]\n"
         "bodies:\n"
         "  floor: {type: fixed, shapes: {surface: {type: halfspace, normal: [0, 0, 1]}}}\n"
         "  a: {type: rigid, mass: 1, position: [0, 0, 0.1], shapes: {ball: {type: sphere, radius: 0.1}}, group: balls}\n"
         "  b: {type: rigid, mass: 1, position: [0, 1, 0.1], shapes: {ball: {type: sphere, radius: 0.1}}, group: balls}\n"
         "  c: {type: rigid, mass: 1, position: [0, 2, 0.1], shapes: {ball: {type: sphere, radius: 0.1}}}\n"
         "contacts:\n"
         "  on_floor: {between: [floor, balls], mu: 0.5}\n"
         "  slippery: {between: [floor, a], mu: 0.05}\n"
         "time: {end: 0.1, step: 1e-3}\n"
         "integrator: {type: moreau-jean, theta: 0.5}\n"
         "contact_solver: {tolerance: 1e-12}\n";
}

TEST(GroupContactLaws, ALawNamingABodyOverridesItsGroupsLaw) {
  const SceneRun run = run_text(override_scene(), "override");
  const World& world = run.scene->world;
  const State& s = run.report.state;
  const double t = 0.1, g_t = 2.0, g_z = 9.81;
  const int a = world.body_index("a"), b = world.body_index("b");
  // Each moving sphere's contact with the floor, under its law.
  ASSERT_EQ(s.contacts.size(), 2u);
  for (const ActiveContact& c : s.contacts) {
    const int sphere = world.bodies[c.body_a].name == "floor" ? c.body_b : c.body_a;
    EXPECT_EQ(world.contact_laws[c.law].name, sphere == a ? "slippery" : "on_floor");
  }
  // Moreau–Jean with θ = ½ integrates a constant acceleration exactly: the velocities to the solver's
  // tolerance (1e-12 relative to a free velocity of g h).
  EXPECT_NEAR(s.v(world.bodies[a].velocity_offset), (g_t - 0.05 * g_z) * t, 1e-9);
  EXPECT_NEAR(s.v(world.bodies[b].velocity_offset), 5.0 / 7.0 * g_t * t, 1e-9);
}

TEST(GroupContactLaws, ABodyInNoLawPassesThrough) {
  const SceneRun run = run_text(override_scene(), "no_law");
  const World& world = run.scene->world;
  const int c = world.body_index("c");
  for (const ActiveContact& contact : run.report.state.contacts) {
    EXPECT_NE(contact.body_a, c);
    EXPECT_NE(contact.body_b, c);
  }
  const double t = 0.1;
  EXPECT_NEAR(run.report.state.q(world.bodies[c].position_offset + 2), 0.1 - 0.5 * 9.81 * t * t, 1e-12);
  EXPECT_NEAR(run.report.state.q(world.bodies[c].position_offset + 0), 0.5 * 2.0 * t * t, 1e-12);
}

}  // namespace
}  // namespace csim
