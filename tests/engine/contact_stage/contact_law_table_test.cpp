// ContactLawTable: which law governs a pair of bodies when laws name bodies or groups, the more
// specific law winning, and the laws of one specificity on one pair refused (contact_law_table.h).
#include "engine/contact_stage/contact_law_table.h"
#include "tests/engine/test_worlds.h"

#include <gtest/gtest.h>

#include <optional>

namespace csim {
namespace {

// Bodies 0–3 in group 0 (G), 4–5 in group 1 (H), 6 in none.
World grouped_world() {
  World world;
  world.dimension = 3;
  for (int i = 0; i < 7; ++i)
    world.bodies.push_back(test::point_mass("p" + std::to_string(i), 3, 1.0, Eigen::Vector3d::Zero()));
  world.groups = {{"G", {0, 1, 2, 3}}, {"H", {4, 5}}};
  for (int i = 0; i < 6; ++i) world.bodies[i].group = i < 4 ? 0 : 1;
  world.finalize_layout();
  return world;
}

ContactLaw law(const std::string& name, int body_a, int group_a, int body_b, int group_b) {
  ContactLaw l;
  l.name = name;
  l.body_a = body_a;
  l.group_a = group_a;
  l.body_b = body_b;
  l.group_b = group_b;
  return l;
}

TEST(ContactLawTable, TheMostSpecificLawGoverns) {
  World world = grouped_world();
  world.contact_laws = {law("GG", -1, 0, -1, 0), law("GH", -1, 0, -1, 1), law("p0_G", 0, -1, -1, 0),
                        law("p1_p2", 1, -1, 2, -1), law("p6_H", 6, -1, -1, 1)};
  const ContactLawTable table(world);
  EXPECT_EQ(table.law(1, 3), 0);  // G × G
  EXPECT_EQ(table.law(3, 1), 0);
  EXPECT_EQ(table.law(2, 5), 1);  // G × H
  EXPECT_EQ(table.law(5, 2), 1);
  EXPECT_EQ(table.law(0, 3), 2);  // p0 × G overrides G × G
  EXPECT_EQ(table.law(3, 0), 2);
  EXPECT_EQ(table.law(0, 4), 1);  // p0 × G does not reach H
  EXPECT_EQ(table.law(1, 2), 3);  // p1 × p2 overrides G × G
  EXPECT_EQ(table.law_by_group(1, 2), 0);
  EXPECT_EQ(table.law(6, 4), 4);
  EXPECT_EQ(table.law(4, 5), -1);  // H × H: no law
  EXPECT_EQ(table.law(6, 0), -1);
  for (int i = 0; i < 7; ++i) EXPECT_TRUE(table.in_some_law(i)) << i;
}

TEST(ContactLawTable, ABodyInNoLawTouchesNothing) {
  World world = grouped_world();
  world.contact_laws = {law("GG", -1, 0, -1, 0)};
  const ContactLawTable table(world);
  for (int i = 4; i < 7; ++i) EXPECT_FALSE(table.in_some_law(i)) << i;
  for (int i = 0; i < 7; ++i) EXPECT_EQ(table.law(i, 6), -1);
}

// The conflict a table of these laws throws, none when it accepts them.
std::optional<ContactLawConflict> conflict_of(const World& world) {
  try {
    const ContactLawTable table(world);
  } catch (const ContactLawConflict& conflict) {
    return conflict;
  }
  return std::nullopt;
}

TEST(ContactLawTable, LawsWithTheSameSidesAreRefused) {
  World world = grouped_world();
  world.contact_laws = {law("GH", -1, 0, -1, 1), law("HG", -1, 1, -1, 0)};
  const std::optional<ContactLawConflict> conflict = conflict_of(world);
  ASSERT_TRUE(conflict) << "accepted";
  EXPECT_EQ(conflict->law, 1);
  EXPECT_EQ(conflict->other, 0);
  EXPECT_EQ(conflict->body_a, -1);
  world.contact_laws = {law("p0_p1", 0, -1, 1, -1), law("p1_p0", 1, -1, 0, -1)};
  EXPECT_THROW(ContactLawTable{world}, ContactLawConflict);
  world.contact_laws = {law("p6_G", 6, -1, -1, 0), law("G_p6", -1, 0, 6, -1)};
  EXPECT_THROW(ContactLawTable{world}, ContactLawConflict);
}

// [p0, H] and [p4, G] both pair p0 with p4 (p0 in G, p4 in H); [p0, G] and [p1, G] both pair p0 with p1.
TEST(ContactLawTable, TwoBodyGroupLawsOnOnePairAreRefusedUnlessABodyPairLawSettlesIt) {
  World world = grouped_world();
  world.contact_laws = {law("p0_H", 0, -1, -1, 1), law("p4_G", 4, -1, -1, 0)};
  const std::optional<ContactLawConflict> conflict = conflict_of(world);
  ASSERT_TRUE(conflict) << "accepted";
  EXPECT_EQ(conflict->law, 1);
  EXPECT_EQ(conflict->other, 0);
  EXPECT_EQ(std::min(conflict->body_a, conflict->body_b), 0);
  EXPECT_EQ(std::max(conflict->body_a, conflict->body_b), 4);
  world.contact_laws.push_back(law("p0_p4", 0, -1, 4, -1));
  const ContactLawTable settled(world);
  EXPECT_EQ(settled.law(0, 4), 2);
  EXPECT_EQ(settled.law(0, 5), 0);
  EXPECT_EQ(settled.law(1, 4), 1);

  world.contact_laws = {law("p0_G", 0, -1, -1, 0), law("p1_G", 1, -1, -1, 0)};
  EXPECT_THROW(ContactLawTable{world}, ContactLawConflict);
  world.contact_laws.push_back(law("p0_p1", 0, -1, 1, -1));
  const ContactLawTable within(world);
  EXPECT_EQ(within.law(0, 1), 2);
  EXPECT_EQ(within.law(0, 2), 0);
  EXPECT_EQ(within.law(1, 3), 1);
  EXPECT_EQ(within.law(2, 3), -1);
}

}  // namespace
}  // namespace csim
