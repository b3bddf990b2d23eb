// ContactDetector on its own: a rigid cube resting on (then lifted above) a fixed halfspace, with the
// gaps, normals, points and rows of H that a hand computation gives.
#include "engine/contact_stage/contact_detector.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>

namespace csim {
namespace {

// scenes/incline-3d flattened (angle 0): a 1 m cube (size 1) of the scene's mass whose centre is at
// z = 0.5, on the halfspace z ≤ 0; the contact law is between [block, slope].
std::unique_ptr<Scene> flat_cube() {
  return load_scene(CSIM_SOURCE_DIR "/scenes/incline-3d/scene.yaml", {"parameters.angle=0", "parameters.size=1"});
}

TEST(ContactDetector, CubeLiftedAboveAHalfspaceHasFourCornerContactsWithTheLiftAsGap) {
  const auto scene = flat_cube();
  const World& world = scene->world;
  ContactDetector detector(world);
  ASSERT_FALSE(detector.empty());
  EXPECT_EQ(detector.dimension(), 3);
  State state = initial_state(world);
  const int block = world.body_index("block");
  const int z = world.bodies[block].position_offset + 2;
  ASSERT_NEAR(state.q(z), 0.5, 1e-15);
  const double lift = 0.01;  // m
  state.q(z) += lift;

  std::vector<ActiveContact> contacts;
  std::vector<SparseRow> rows;
  detector.detect(state.q, 2 * lift, contacts, rows);
  ASSERT_EQ(contacts.size(), 4u);  // the four bottom corners
  ASSERT_EQ(rows.size(), 3 * contacts.size());
  for (const ActiveContact& c : contacts) {
    EXPECT_NEAR(c.point.gap, lift, 1e-12);
    EXPECT_NEAR(std::abs(c.point.normal.z()), 1.0, 1e-12);  // along z, from the point's body A to B
    EXPECT_NEAR(c.point.normal.dot(c.point.t1), 0.0, 1e-12);
    EXPECT_NEAR(c.point.normal.dot(c.point.t2), 0.0, 1e-12);
    // The cube's side of the point is one of its bottom corners (x, y = ±0.5, z = lift).
    const Eigen::Vector3d corner = c.body_a == block ? c.point.point_a : c.point.point_b;
    EXPECT_NEAR(std::abs(corner.x()), 0.5, 1e-12);
    EXPECT_NEAR(std::abs(corner.y()), 0.5, 1e-12);
    EXPECT_NEAR(corner.z(), lift, 1e-12);
  }
  // Margin below the lift: nothing.
  detector.detect(state.q, 0.5 * lift, contacts, rows);
  EXPECT_TRUE(contacts.empty());
}

TEST(ContactDetector, RowsOfHGiveTheRelativeVelocityAtTheCorners) {
  const auto scene = flat_cube();
  const World& world = scene->world;
  ContactDetector detector(world);
  State state = initial_state(world);
  std::vector<ActiveContact> contacts;
  std::vector<SparseRow> rows;
  detector.detect(state.q, 1e-6, contacts, rows);
  ASSERT_EQ(contacts.size(), 4u);
  for (const ActiveContact& c : contacts) EXPECT_NEAR(c.point.gap, 0.0, 1e-12);  // resting

  const int block = world.body_index("block");
  const int offset = world.bodies[block].velocity_offset;
  // Falling at 1 m/s: every corner approaches, u_n = −1 m/s, no slip.
  Vector v = Vector::Zero(world.velocity_size);
  v(offset + 2) = -1.0;
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    EXPECT_NEAR(rows[3 * i].dot(v), -1.0, 1e-12);
    EXPECT_NEAR(rows[3 * i + 1].dot(v), 0.0, 1e-12);
    EXPECT_NEAR(rows[3 * i + 2].dot(v), 0.0, 1e-12);
  }
  // Spinning about z at 2 rad/s (the angular velocity's z component, whatever the body's convention
  // of frame, is the same for this upright cube): a corner at r = (±0.5, ±0.5) slides at ω × r, of
  // speed 2 · √0.5 m/s, tangential only.
  v.setZero();
  v(offset + 5) = 2.0;
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    EXPECT_NEAR(rows[3 * i].dot(v), 0.0, 1e-12);
    EXPECT_NEAR(std::hypot(rows[3 * i + 1].dot(v), rows[3 * i + 2].dot(v)), 2.0 * std::sqrt(0.5), 1e-12);
  }
}

TEST(ContactDetector, TravelBoundCoversTheFastestPoint) {
  const auto scene = flat_cube();
  const World& world = scene->world;
  ContactDetector detector(world);
  const int offset = world.bodies[world.body_index("block")].velocity_offset;
  Vector v = Vector::Zero(world.velocity_size);
  v(offset) = 3.0;  // m/s
  EXPECT_GE(detector.travel_bound(v, 0.1), 0.3 - 1e-15);
  v(offset + 5) = 2.0;  // rad/s: a corner at √0.5 m moves 2 √0.5 m/s more
  EXPECT_GE(detector.travel_bound(v, 0.1), 0.1 * (3.0 + 2.0 * std::sqrt(0.5)) - 1e-12);
}

// contact_rows appends a column of J at a time when no velocity component can appear twice (two
// bodies, neither naming a component twice): the rows must be SparseRow::add's, entry for entry and
// to the bit; a body on both sides, or a Jacobian naming a component twice, merges its entries.
TEST(ContactDetector, ContactRowsAreThoseOfSparseRowAddToTheBit) {
  const auto scene = flat_cube();
  const World& world = scene->world;
  const int block = world.body_index("block"), slope = world.body_index("slope");
  ContactPoint c;
  c.normal = Eigen::Vector3d(0.1, -0.3, 0.9).normalized();
  complete_frame(c, false);
  auto jacobian = [](std::vector<int> components, double seed) {
    PointJacobian J;
    for (int component : components)
      J.add(component, Eigen::Vector3d(std::sin(seed + component), std::cos(3.0 * seed + component), 0.7 - seed));
    return J;
  };
  auto by_add = [&](int body_a, const PointJacobian& a, int body_b, const PointJacobian& b) {
    std::vector<SparseRow> rows(3);
    const Eigen::Vector3d* axes[3] = {&c.normal, &c.t1, &c.t2};
    const int ids[2] = {body_a, body_b};
    const PointJacobian* sides[2] = {&a, &b};
    for (int side = 0; side < 2; ++side)
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < sides[side]->count; ++j)
          rows[k].add(world.bodies[ids[side]].velocity_offset + sides[side]->index[j],
                      (side == 0 ? -1.0 : 1.0) * axes[k]->dot(sides[side]->column.col(j)));
    return rows;
  };
  const PointJacobian none, rigid = jacobian({0, 1, 2, 3, 4, 5}, 0.3), other = jacobian({0, 1, 2, 3, 4, 5}, 1.1),
                      repeated = jacobian({0, 3, 0, 4}, 0.5);
  PointJacobian translation;  // unit and zero columns: products of zero, and signed zeros in the rows
  translation.add(0, Eigen::Vector3d::UnitX());
  translation.add(1, Eigen::Vector3d::UnitY());
  translation.add(2, Eigen::Vector3d(0.0, -0.0, 0.0));
  struct Case {
    int body_a, body_b;
    const PointJacobian *a, *b;
    int entries;  // per row
  };
  const std::vector<Case> cases = {
      {block, slope, &rigid, &none, 6},
      {slope, block, &none, &other, 6},
      {block, block, &rigid, &other, 6},     // one body on both sides: merged
      {block, slope, &repeated, &none, 3},  // component 0 twice: merged
      {block, slope, &rigid, &other, 12},   // both sides, two bodies (slope's offset past block's)
      {slope, block, &translation, &rigid, 9},
  };
  for (const Case& test : cases)
    for (int dimension : {3, 2}) {  // a plane contact's rows are the first two
      std::vector<SparseRow> rows(3);
      contact_rows(world, test.body_a, *test.a, test.body_b, *test.b, c, dimension, rows.data());
      const std::vector<SparseRow> expected = by_add(test.body_a, *test.a, test.body_b, *test.b);
      for (int k = 0; k < dimension; ++k) {
        EXPECT_EQ(rows[k].count, test.entries);
        EXPECT_TRUE(rows[k] == expected[k]) << "bodies " << test.body_a << ", " << test.body_b << ", row " << k;
        EXPECT_EQ(std::memcmp(rows[k].value.data(), expected[k].value.data(), rows[k].count * sizeof(double)), 0)
            << "signs of zero, bodies " << test.body_a << ", " << test.body_b << ", row " << k;
      }
    }
}

// A detection's rows between two bodies' shapes come from each side's Jacobian projected by its body
// (Body::project_world_point_jacobian, from the world lever arm): the rows of contact_rows with
// side_jacobian (Body::world_point_jacobian: pose⁻¹, the body-frame point) to round-off, entry for
// entry, at the next detection's q and not the last one's.
TEST(ContactDetector, RowsAreThoseOfEachSidesJacobianAtTheDetectionsQToRoundOff) {
  for (const char* name : {"incline-3d", "sdnv104-rigid"}) {
    const auto scene = load_scene(std::string(CSIM_SOURCE_DIR "/scenes/") + name + "/scene.yaml", {});
    const World& world = scene->world;
    ContactDetector detector(world);
    const int d = detector.dimension();
    State state = initial_state(world);
    const int moving = world.body_index(d == 3 ? "block" : "shoe");
    std::vector<ActiveContact> contacts;
    std::vector<SparseRow> rows;
    for (const double shift : {0.0, 0.3, -0.2}) {
      Vector q = state.q;
      q(world.bodies[moving].position_offset + (d == 3 ? 1 : 0)) += shift;  // along the surface: elsewhere on it
      detector.detect(q, 1e-6, contacts, rows);
      ASSERT_EQ(contacts.size(), d == 3 ? 4u : 2u) << name << " " << shift;
      for (std::size_t i = 0; i < contacts.size(); ++i) {
        const ContactPoint& c = contacts[i].point;
        SparseRow expected[3];
        contact_rows(world, contacts[i].body_a, detector.side_jacobian(q, c.key.object_a, c, c.point_a),
                     contacts[i].body_b, detector.side_jacobian(q, c.key.object_b, c, c.point_b), c, d, expected);
        for (int k = 0; k < d; ++k) {
          const SparseRow& row = rows[d * i + k];
          ASSERT_EQ(row.count, expected[k].count) << name << " " << shift << ", contact " << i << ", row " << k;
          for (int j = 0; j < row.count; ++j) {
            EXPECT_EQ(row.index[j], expected[k].index[j]);
            EXPECT_NEAR(row.value[j], expected[k].value[j], 1e-15 * (1.0 + std::abs(expected[k].value[j])))
                << name << " " << shift << ", contact " << i << ", row " << k << ", entry " << j;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace csim
