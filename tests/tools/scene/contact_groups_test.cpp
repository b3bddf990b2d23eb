// Contact laws by group (docs/contract.md, contacts): a body's `group`, a law's `between` naming bodies
// or groups, the precedence of the more specific law, and the scenes refused before the first step
// with the file, the line and the key.
#include "tests/tools/scene/scene_file_test.h"
#include "tools/scene/contact_pairs_listing.h"
#include "engine/contact_stage/contact_law_table.h"

#include <gtest/gtest.h>

namespace csim {
namespace {

// Line 5: a, 6: b (group balls), 7: c (group others), 8: d (no group), 10 on: the laws.
std::string scene(const std::string& contacts, const std::string& extra_bodies = "") {
  return "dimension: 3\n"
         "bodies:\n"
         "  floor: {type: fixed, shapes: {surface: {type: halfspace, normal: [0, 0, 1]}}}\n"
         "  # spheres of 0.1 m, 0.3 m apart\n"
         "  a: {type: rigid, mass: 1, position: [0, 0, 0.1], shapes: {ball: {type: sphere, radius: 0.1}}, group: balls}\n"
         "  b: {type: rigid, mass: 1, position: [0.3, 0, 0.1], shapes: {ball: {type: sphere, radius: 0.1}}, group: balls}\n"
         "  c: {type: rigid, mass: 1, position: [0.6, 0, 0.1], shapes: {ball: {type: sphere, radius: 0.1}}, group: others}\n"
         "  d: {type: rigid, mass: 1, position: [0.9, 0, 0.1], shapes: {ball: {type: sphere, radius: 0.1}}}\n" +
         extra_bodies + "contacts:\n" + contacts + "time: {end: 0.01, step: 1e-3}\n";
}

class ContactGroups : public SceneFileTest {};

TEST_F(ContactGroups, GroupsAndLawSidesAreRead) {
  const auto loaded = load_scene(write(scene("  pile: {between: [balls, balls], mu: 0.5}\n"
                                             "  floor_law: {between: [floor, balls], mu: 0.4}\n"
                                             "  mixed: {between: [balls, others], mu: 0.3}\n"
                                             "  pair: {between: [a, b], mu: 0.1}\n")),
                                 {});
  const World& world = loaded->world;
  ASSERT_EQ(world.groups.size(), 2u);
  EXPECT_EQ(world.groups[0].name, "balls");
  EXPECT_EQ(world.groups[0].bodies, (std::vector<int>{1, 2}));
  EXPECT_EQ(world.groups[1].bodies, (std::vector<int>{3}));
  EXPECT_EQ(world.bodies[4].group, -1);
  const ContactLaw& pile = world.contact_laws[0];
  EXPECT_EQ(pile.group_a, 0);
  EXPECT_EQ(pile.group_b, 0);
  EXPECT_EQ(pile.body_a, -1);
  EXPECT_FALSE(pile.between_bodies());
  EXPECT_EQ(world.contact_laws[1].body_a, 0);
  EXPECT_EQ(world.contact_laws[1].group_b, 0);
  EXPECT_TRUE(world.contact_laws[3].between_bodies());

  // The pair a–b takes the law naming both; a body of balls against c, the group law; d touches nothing.
  const ContactLawTable table(world);
  EXPECT_EQ(table.law(1, 2), 3);
  EXPECT_EQ(table.law(2, 1), 3);
  EXPECT_EQ(table.law_by_group(1, 2), 0);
  EXPECT_EQ(table.law(1, 3), 2);
  EXPECT_EQ(table.law(0, 2), 1);
  EXPECT_EQ(table.law(0, 3), -1);  // floor × others: no law
  EXPECT_EQ(table.law(3, 4), -1);
  EXPECT_FALSE(table.in_some_law(4));

  const std::string listing = contact_pairs_listing(world);
  EXPECT_NE(listing.find("group balls × group balls: law pile (μ 0.5, e 0)"), std::string::npos) << listing;
  EXPECT_NE(listing.find("body floor × group balls: law floor_law (μ 0.4, e 0)"), std::string::npos) << listing;
  EXPECT_NE(listing.find("body a × body b: law pair (μ 0.1, e 0; overrides pile)"), std::string::npos) << listing;
  EXPECT_NE(listing.find("bodies in no contact law (they touch nothing): 1: d"), std::string::npos) << listing;
}

TEST_F(ContactGroups, ABodyAndAGroupOverrideTwoGroups) {
  const auto loaded = load_scene(write(scene("  pile: {between: [balls, balls], mu: 0.5}\n"
                                             "  a_in_pile: {between: [balls, a], mu: 0.2}\n")),
                                 {});
  const ContactLawTable table(loaded->world);
  EXPECT_EQ(table.law(1, 2), 1);
  EXPECT_NE(contact_pairs_listing(loaded->world).find("group balls × body a: law a_in_pile (μ 0.2, e 0; overrides pile)"),
            std::string::npos);
}

TEST_F(ContactGroups, ANameOfABodyAndAGroupIsRefused) {
  const std::string message = error_of(write(scene("  pile: {between: [balls, balls]}\n",
                                                   "  e: {type: rigid, mass: 1, shapes: {ball: {type: sphere, radius: 0.1}}, group: d}\n")));
  EXPECT_NE(message.find(".yaml:9: bodies.e.group: 'd' is also the name of a body"), std::string::npos) << message;
}

TEST_F(ContactGroups, AnUnknownSideIsRefused) {
  const std::string message = error_of(write(scene("  pile: {between: [balls, marbles]}\n")));
  EXPECT_NE(message.find(".yaml:10: contacts.pile.between"), std::string::npos) << message;
  EXPECT_NE(message.find("no body or group named 'marbles'"), std::string::npos) << message;
}

TEST_F(ContactGroups, TwoLawsWithTheSameSidesAreRefused) {
  std::string message = error_of(write(scene("  pile: {between: [balls, balls]}\n  again: {between: [balls, balls]}\n")));
  EXPECT_NE(message.find(".yaml:11: contacts.again.between: the contact law 'pile' has the same sides"), std::string::npos)
      << message;
  message = error_of(write(scene("  one: {between: [floor, balls]}\n  two: {between: [balls, floor]}\n")));
  EXPECT_NE(message.find(".yaml:11: contacts.two.between: the contact law 'one' has the same sides"), std::string::npos)
      << message;
  message = error_of(write(scene("  one: {between: [a, b]}\n  two: {between: [b, a]}\n")));
  EXPECT_NE(message.find(".yaml:11: contacts.two.between: the contact law 'one' has the same sides"), std::string::npos)
      << message;
}

TEST_F(ContactGroups, TwoBodyGroupLawsOnOnePairAreRefusedUnlessABodyPairLawSettlesIt) {
  // [a, others] and [c, balls] both pair a with c (a is in balls, c in others).
  const std::string laws = "  a_others: {between: [a, others]}\n  c_balls: {between: [c, balls]}\n";
  const std::string message = error_of(write(scene(laws)));
  EXPECT_NE(message.find(".yaml:11: contacts.c_balls.between: the contact laws 'a_others' and 'c_balls' both pair the "
                         "bodies"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("'a' and 'c'"), std::string::npos) << message;
  const auto settled = load_scene(write(scene(laws + "  a_c: {between: [a, c], mu: 0.7}\n")), {});
  const ContactLawTable table(settled->world);
  EXPECT_EQ(table.law(1, 3), 2);
  EXPECT_EQ(table.law(2, 3), 1);  // b–c: c_balls alone
}

TEST_F(ContactGroups, AGroupOfOneAgainstItselfIsRefused) {
  const std::string message = error_of(write(scene("  lonely: {between: [others, others]}\n")));
  EXPECT_NE(message.find(".yaml:10: contacts.lonely.between: this law pairs no two distinct bodies"), std::string::npos)
      << message;
  EXPECT_NE(error_of(write(scene("  lonely: {between: [c, others]}\n"))).find("pairs no two distinct bodies"),
            std::string::npos);
}

TEST_F(ContactGroups, AGroupWithABodyWithoutShapesIsRefused) {
  const std::string message = error_of(write(scene("  pile: {between: [floor, balls]}\n",
                                                   "  p: {type: point, mass: 1, group: balls}\n")));
  EXPECT_NE(message.find(".yaml:11: contacts.pile.between: body 'p' (of group 'balls') has no shapes"), std::string::npos)
      << message;
}

// Two elastic blocks in one group: a group law pairing them is refused, a law of the group against a
// rigid body is not.
std::string elastic_scene(const std::string& contacts) {
  return "dimension: 2\n"
         "bodies:\n"
         "  left: {type: elastic, mesh: {generator: rectangle, size: [1, 0.25], divisions: [2, 1], element: quad4},\n"
         "         material: {young: 1e9, poisson: 0.3, density: 1000}, group: blocks}\n"
         "  right: {type: elastic, mesh: {generator: rectangle, size: [1, 0.25], divisions: [2, 1], element: quad4},\n"
         "          material: {young: 1e9, poisson: 0.3, density: 1000}, group: blocks}\n"
         "  ground: {type: fixed, shapes: {surface: {type: halfspace, normal: [0, 1], offset: -0.1}}}\n"
         "contacts:\n" +
         contacts + "time: {end: 0.01, step: 1e-3}\n";
}

TEST_F(ContactGroups, AGroupLawPairingTwoElasticBodiesIsRefused) {
  const std::string message = error_of(write(elastic_scene("  blocks: {between: [blocks, blocks]}\n")));
  EXPECT_NE(message.find(".yaml:9: contacts.blocks.between: contact between two elastic bodies ('left' and 'right') "
                         "is not supported"),
            std::string::npos)
      << message;
  EXPECT_EQ(error_of(write(elastic_scene("  on_ground: {between: [ground, blocks], features: nodes}\n"))), "");
}

TEST_F(ContactGroups, AForceProbeNeedsABodyAsTheLawsFirstSide) {
  const std::string probes = "probes:\n  push: {contact_force: {contact: pile, component: x}}\n";
  const std::string message = error_of(write(scene("  pile: {between: [balls, balls]}\n") + probes));
  EXPECT_NE(message.find("probes.push.contact_force.component: contact law 'pile' names the group 'balls' first"),
            std::string::npos)
      << message;
  EXPECT_EQ(error_of(write(scene("  pile: {between: [balls, balls]}\n") +
                           "probes:\n  load: {contact_force: {contact: pile, component: normal}}\n")),
            "");
  EXPECT_EQ(error_of(write(scene("  pile: {between: [floor, balls]}\n") +
                           "probes:\n  push: {contact_force: {contact: pile, component: x}}\n")),
            "");
}

TEST_F(ContactGroups, IdaRefusesGroupLaws) {
  const std::string message =
      error_of(write(scene("  pile: {between: [balls, balls]}\n") + "integrator: {type: ida}\n"));
  EXPECT_NE(message.find("integrator.type: ida takes contact laws between two bodies (contact law 'pile' names a group)"),
            std::string::npos)
      << message;
}

}  // namespace
}  // namespace csim
