// A body's `copies` (docs/contract.md, bodies): a grid of bodies from one entry, named NAME_n (x
// slowest), placed at position + (i dx, j dy, k dz), in the group NAME unless the entry names its own;
// a pile written this way runs as the same pile written body by body; names that clash are refused
// with the file, the line and the key.
#include "tests/tools/scene/scene_file_test.h"
#include "tools/run/run.h"
#include "tools/scene/contact_pairs_listing.h"

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

namespace csim {
namespace {

// Line 3: floor, 4: balls (3 × 2 × 2 spheres of 0.1 m, stacked 0.2 m apart in z, 0.25 m in x and y).
std::string scene(const std::string& balls_extra = "", const std::string& extra_bodies = "") {
  return "dimension: 3\n"
         "bodies:\n"
         "  floor: {type: fixed, shapes: {surface: {type: halfspace, normal: [0, 0, 1]}}}\n"
         "  balls: {type: rigid, mass: 1, position: [0, 0, 0.1], shapes: {ball: {type: sphere, radius: 0.1}},"
         " copies: {grid: [3, 2, 2], spacing: [0.25, 0.25, 0.2]}" + balls_extra + "}\n" + extra_bodies +
         "contacts:\n"
         "  pile: {between: [balls, balls], mu: 0.5}\n"
         "  ground: {between: [balls, floor], mu: 0.5}\n"
         "gravity: [0, 0, -9.81]\n"
         "time: {end: 0.05, step: 1e-3}\n";
}

class BodyCopies : public SceneFileTest {};

TEST_F(BodyCopies, AGridOfNamedBodiesInOneGroup) {
  const auto loaded = load_scene(write(scene()), {});
  const World& world = loaded->world;
  ASSERT_EQ(world.bodies.size(), 1u + 12u);
  ASSERT_EQ(world.groups.size(), 1u);
  EXPECT_EQ(world.groups[0].name, "balls");
  EXPECT_EQ(world.groups[0].bodies.size(), 12u);
  for (int n = 0; n < 12; ++n) {
    const BodyInstance& b = world.bodies[world.body_index("balls_" + std::to_string(n))];
    const int i = n / 4, j = (n / 2) % 2, k = n % 2;  // n = (i · 2 + j) · 2 + k
    EXPECT_NEAR(b.initial_position(0), 0.25 * i, 1e-15) << b.name;
    EXPECT_NEAR(b.initial_position(1), 0.25 * j, 1e-15) << b.name;
    EXPECT_NEAR(b.initial_position(2), 0.1 + 0.2 * k, 1e-15) << b.name;
    EXPECT_EQ(b.group, 0);
  }
}

TEST_F(BodyCopies, TheStacksStandOnTheFloor) {
  // Six stacks of two touching spheres: every upper sphere on its lower one, every lower one on the
  // floor, all at rest: 12 contacts, the floor carrying the 12 spheres' weight each step.
  const RunReport report = run_scene(*load_scene(write(scene()), {}), {});
  EXPECT_EQ(report.state.contacts.size(), 12u);
  EXPECT_EQ(report.state.counters.not_converged, 0);
  EXPECT_LE(report.state.v.lpNorm<Eigen::Infinity>(), 0.01 * 9.81 * 1e-3);
}

TEST_F(BodyCopies, ACopyNamedLikeAnotherBodyIsRefused) {
  const std::string message =
      error_of(write(scene("", "  balls_3: {type: rigid, mass: 1, shapes: {ball: {type: sphere, radius: 0.1}}}\n")));
  EXPECT_NE(message.find(".yaml:4: bodies.balls.copies: the copy 'balls_3' has the name of another body"),
            std::string::npos) << message;
}

TEST_F(BodyCopies, AGridWithTheWrongCountIsRefused) {
  std::string text = scene();
  text.replace(text.find("[3, 2, 2]"), 9, "[3, 2]");
  const std::string message = error_of(write(text));
  EXPECT_NE(message.find("bodies.balls.copies.grid: expected 3 counts, one per axis"), std::string::npos) << message;
  text = scene();
  text.replace(text.find("[3, 2, 2]"), 9, "[3, 0.5, 2]");
  EXPECT_NE(error_of(write(text)).find("each count must be a whole number >= 1"), std::string::npos);
}

TEST_F(BodyCopies, CopiesMayJoinANamedGroup) {
  std::string text = scene(", group: marbles");
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"[balls, balls]", "[marbles, marbles]"}, {"[balls, floor]", "[marbles, floor]"}})
    text.replace(text.find(from), from.size(), to);
  const auto loaded = load_scene(write(text), {});
  ASSERT_EQ(loaded->world.groups.size(), 1u);
  EXPECT_EQ(loaded->world.groups[0].name, "marbles");
  EXPECT_EQ(loaded->world.groups[0].bodies.size(), 12u);
}

// A law with collide: false, naming two bodies of the group, overrides the group's law on that pair:
// the upper sphere of the first stack falls through the lower one as if it were not there (½ g t² in
// 0.05 s, no floor within reach), while the other stacks stand.
TEST_F(BodyCopies, APairThatNeverCollides) {
  std::string text = scene();
  const std::string laws = "  ground: {between: [balls, floor], mu: 0.5}\n";
  text.replace(text.find(laws), laws.size(), laws + "  apart: {between: [balls_0, balls_1], collide: false}\n");
  const auto loaded = load_scene(write(text), {});
  EXPECT_NE(contact_pairs_listing(loaded->world).find("body balls_0 × body balls_1: law apart (never collide; overrides pile)"),
            std::string::npos) << contact_pairs_listing(loaded->world);
  const RunReport report = run_scene(*loaded, {});
  const World& world = loaded->world;
  const auto z = [&](const std::string& name) {
    const BodyInstance& b = world.bodies[world.body_index(name)];
    return report.state.q(b.position_offset + 2);
  };
  const double t = report.state.t, g = 9.81;
  EXPECT_NEAR(z("balls_1"), 0.3 - 0.5 * g * t * t, 1e-9);
  EXPECT_NEAR(z("balls_0"), 0.1, 1e-9);
  EXPECT_NEAR(z("balls_3"), 0.3, 1e-9);  // the next stack's upper sphere stands
  EXPECT_EQ(report.state.contacts.size(), 11u);
}

TEST_F(BodyCopies, ALawThatNeverCollidesTakesNoFriction) {
  std::string text = scene();
  const std::string laws = "  ground: {between: [balls, floor], mu: 0.5}\n";
  text.replace(text.find(laws), laws.size(), laws + "  apart: {between: [balls_0, balls_1], collide: false, mu: 0.3}\n");
  const std::string message = error_of(write(text));
  EXPECT_NE(message.find("contacts.apart.mu: a law whose pairs never collide (collide: false) takes no mu"),
            std::string::npos) << message;
  // ida sets its contacts by law: it refuses such a law before the first step.
  const std::string refused = error_of(write(
      "dimension: 3\n"
      "bodies:\n"
      "  floor: {type: fixed, shapes: {surface: {type: halfspace, normal: [0, 0, 1]}}}\n"
      "  a: {type: rigid, mass: 1, position: [0, 0, 0.1], shapes: {ball: {type: sphere, radius: 0.1}}}\n"
      "  b: {type: rigid, mass: 1, position: [0, 0, 0.3], shapes: {ball: {type: sphere, radius: 0.1}}}\n"
      "contacts:\n"
      "  ground: {between: [a, floor], mu: 0.5}\n"
      "  apart: {between: [a, b], collide: false}\n"
      "integrator: {type: ida}\n"
      "time: {end: 0.01, step: 1e-3}\n"));
  EXPECT_NE(refused.find("contact law 'apart': collide: false); use moreau-jean"), std::string::npos) << refused;
}

}  // namespace
}  // namespace csim
