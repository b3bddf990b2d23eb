// Box–box manifolds through CollisionWorld (FCL names the normal, face clipping gives the points)
// against closed forms: the points of a box resting on another are the corners of the overlap of the
// touching faces, each with its exact gap. Tolerances: kFcl (1e-9 m) where FCL's normal enters,
// kExact (1e-12 m) for gaps of points whose normal is a face normal.
#include "contact/convex_manifold.h"
#include "contact/narrow_phase.h"
#include "tests/contact/detection_test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace csim {
namespace {

using namespace detection_test;

// The scene's frame: points given in a local frame where the lower box's top face is z = 0.
Eigen::Vector3d world(const Eigen::Vector3d& local) { return kScene * local; }
Eigen::Vector3d world_direction(const Eigen::Vector3d& local) { return kScene.linear() * local; }

// A box of half extents h whose centre is at `centre` in the local frame, turned by `turn`.
Placed local_box(const Eigen::Vector3d& h, const Eigen::Vector3d& centre,
                 const Eigen::Isometry3d& turn = Eigen::Isometry3d::Identity()) {
  return {Box{h}, kScene * translation(centre.x(), centre.y(), centre.z()) * turn};
}

// The lower box: a slab whose top face is the local plane z = 0.
const Placed kSlab = local_box({1.0, 0.8, 0.5}, {0.0, 0.0, -0.5});

// Points of `contacts` seen from the upper box (second registered: B), in the local frame.
std::vector<Eigen::Vector3d> upper_points(const std::vector<ContactPoint>& contacts) {
  std::vector<Eigen::Vector3d> points;
  for (const ContactPoint& c : contacts) points.push_back(kScene.inverse() * c.point_b);
  // By x, then y, each read to 1e-9 m so that round-off does not reorder equal coordinates.
  auto key = [](const Eigen::Vector3d& p) { return std::make_pair(std::lround(p.x() * 1e9), std::lround(p.y() * 1e9)); };
  std::sort(points.begin(), points.end(),
            [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return key(a) < key(b); });
  return points;
}

// Every contact: normal +z (from the slab up), gap = the upper point's height, the slab's point on z = 0.
void expect_resting(const std::vector<ContactPoint>& contacts, double tol) {
  for (const ContactPoint& c : contacts) {
    expect_near(c.normal, world_direction(Eigen::Vector3d::UnitZ()), tol);
    const Eigen::Vector3d a = kScene.inverse() * c.point_a;
    const Eigen::Vector3d b = kScene.inverse() * c.point_b;
    EXPECT_NEAR(a.z(), 0.0, tol);
    EXPECT_NEAR(c.gap, b.z(), tol);
  }
}

TEST(BoxBoxManifold, CubeOnASlabGivesItsFourBottomVertices) {
  for (double gap : {0.05, 2e-6, 5e-7, 0.0, -1e-12, -0.01}) {
    SCOPED_TRACE(gap);
    const Placed cube = local_box(Eigen::Vector3d::Constant(0.3), {0.2, -0.1, 0.3 + gap});
    for (bool reversed : {false, true}) {
      const auto contacts = detect(kSlab, cube, 0.1, reversed);
      ASSERT_EQ(contacts.size(), 4u);
      std::vector<int> features;
      for (const ContactPoint& c : contacts) {
        // Each point is a bottom vertex of the cube (a material point: its arm is set), at the gap.
        EXPECT_NEAR(c.gap, gap, kExact);
        const bool cube_is_b = !reversed;
        const Eigen::Vector3d& arm = cube_is_b ? c.arm_b : c.arm_a;
        const Eigen::Vector3d& on_cube = cube_is_b ? c.point_b : c.point_a;
        ASSERT_FALSE(std::isnan(arm.x()));
        const int vertex = c.key.feature % 128;
        ASSERT_LT(vertex, 8);
        features.push_back(vertex);
        expect_near(on_cube, cube.pose * box_vertex(std::get<Box>(cube.shape), vertex, false), kExact);
        expect_near(arm, cube.pose.linear() * box_vertex(std::get<Box>(cube.shape), vertex, false), kExact);
      }
      std::sort(features.begin(), features.end());
      // The cube's bottom face (local z < 0 in its frame): vertices 0..3 of box_vertex's numbering.
      EXPECT_EQ(features, (std::vector<int>{0, 1, 2, 3}));
      if (!reversed) expect_resting(contacts, kExact);
    }
  }
}

TEST(BoxBoxManifold, EqualCubesStackedGiveFourPointsNotDuplicates) {
  // A tower of equal cubes puts every incident vertex on a reference corner; offsets at round-off
  // level must not double the points or drop them.
  const Eigen::Vector3d h = Eigen::Vector3d::Constant(0.25);
  const Placed lower = local_box(h, {0.0, 0.0, -0.25});
  for (double offset : {0.0, 1e-14, -1e-14, 1e-11}) {
    SCOPED_TRACE(offset);
    const Placed upper = local_box(h, {offset, -offset, 0.25 + 1e-7});
    const auto contacts = detect(lower, upper, 0.01);
    ASSERT_EQ(contacts.size(), 4u);
    expect_resting(contacts, 1e-12);
    for (const Eigen::Vector3d& p : upper_points(contacts)) {
      EXPECT_NEAR(std::abs(p.x()), 0.25, 1e-10);
      EXPECT_NEAR(std::abs(p.y()), 0.25, 1e-10);
      EXPECT_NEAR(p.z(), 1e-7, 1e-12);
    }
  }
}

TEST(BoxBoxManifold, OffsetCubeGivesTheCornersOfTheOverlap) {
  // Equal cubes (half size 0.25), the upper one moved by (0.2, 0.1): the overlap of the faces is
  // [−0.05, 0.25] × [−0.15, 0.25]; two corners are the upper cube's vertices, one the lower cube's,
  // one the crossing of their edges.
  const Eigen::Vector3d h = Eigen::Vector3d::Constant(0.25);
  const Placed lower = local_box(h, {0.0, 0.0, -0.25});
  const Placed upper = local_box(h, {0.2, 0.1, 0.25 + 0.003});
  for (bool reversed : {false, true}) {
    SCOPED_TRACE(reversed);
    auto contacts = detect(lower, upper, 0.01, reversed);
    ASSERT_EQ(contacts.size(), 4u);
    for (ContactPoint& c : contacts) {
      EXPECT_NEAR(c.gap, 0.003, kExact);
      if (reversed) std::swap(c.point_a, c.point_b);
    }
    const auto points = upper_points(contacts);
    const std::vector<Eigen::Vector3d> expected = {
        {-0.05, -0.15, 0.003}, {-0.05, 0.25, 0.003}, {0.25, -0.15, 0.003}, {0.25, 0.25, 0.003}};
    for (std::size_t i = 0; i < 4; ++i) expect_near(points[i], expected[i], 1e-12);
  }
}

TEST(BoxBoxManifold, CubeTurnedOnAnEqualCubeKeepsFourOfTheOctagonsVertices) {
  // Turned by 45° about the normal, the faces overlap in a regular octagon of circumradius
  // R = h √(4 − 2√2); the four points kept span the largest quadrilateral: alternate vertices,
  // area 2 R².
  const double h = 0.25;
  const Placed lower = local_box(Eigen::Vector3d::Constant(h), {0.0, 0.0, -h});
  const Placed upper = local_box(Eigen::Vector3d::Constant(h), {0.0, 0.0, h - 0.002},
                                 rotation(kPi / 4.0, {0, 0, 1}));
  const auto contacts = detect(lower, upper, 0.01);
  ASSERT_EQ(contacts.size(), 4u);
  expect_resting(contacts, 1e-12);
  const double radius = h * std::sqrt(4.0 - 2.0 * std::sqrt(2.0));
  std::vector<Eigen::Vector3d> points = upper_points(contacts);
  for (const Eigen::Vector3d& p : points) {
    EXPECT_NEAR(p.z(), -0.002, 1e-12);
    EXPECT_NEAR(std::hypot(p.x(), p.y()), radius, 1e-12);
  }
  // The four points' hull, ordered by angle.
  std::sort(points.begin(), points.end(), [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::atan2(a.y(), a.x()) < std::atan2(b.y(), b.x());
  });
  double area = 0.0;
  for (std::size_t i = 0; i < 4; ++i) {
    const Eigen::Vector3d& p = points[i];
    const Eigen::Vector3d& q = points[(i + 1) % 4];
    area += 0.5 * (p.x() * q.y() - p.y() * q.x());
  }
  EXPECT_NEAR(area, 2.0 * radius * radius, 1e-12);
}

TEST(BoxBoxManifold, CubeTiltedOntoAnEdgeGivesTheEdgesTwoVertices) {
  // Turned by 10° about y, the cube's lowest edge (parallel to y) hangs `gap` above the slab: two
  // points, at the edge's ends; the other vertices are beyond the margin.
  const double h = 0.2;
  const double angle = 10.0 * kPi / 180.0;
  const double reach = h * (std::cos(angle) + std::sin(angle));  // centre height above the lowest edge
  for (double gap : {1e-3, 0.0, -1e-3}) {
    SCOPED_TRACE(gap);
    const Placed cube = local_box(Eigen::Vector3d::Constant(h), {0.1, 0.0, reach + gap},
                                  rotation(angle, {0, 1, 0}));
    const auto contacts = detect(kSlab, cube, 0.01);
    ASSERT_EQ(contacts.size(), 2u);
    expect_resting(contacts, kExact);
    const auto points = upper_points(contacts);
    // The lowest edge: at x = 0.1 + h (cos − sin) in the local frame, y = ±h.
    const double x = 0.1 + h * (std::cos(angle) - std::sin(angle));
    expect_near(points[0], {x, -h, gap}, 1e-12);
    expect_near(points[1], {x, h, gap}, 1e-12);
  }
}

TEST(BoxBoxManifold, CrossedEdgesKeepFclsSinglePoint) {
  // Each cube turned 45° so that an edge faces the other, the edges crossed at right angles: the
  // contact is edge–edge, one point, normal along the line of centres, gap = distance − 2 h √2.
  const double h = 0.2;
  const Placed lower = local_box(Eigen::Vector3d::Constant(h), {0, 0, -h * std::sqrt(2.0)},
                                 rotation(kPi / 4.0, {1, 0, 0}));
  for (double gap : {0.004, -0.004}) {
    SCOPED_TRACE(gap);
    const Placed upper = local_box(Eigen::Vector3d::Constant(h), {0, 0, h * std::sqrt(2.0) + gap},
                                   rotation(kPi / 4.0, {0, 1, 0}));
    expect_single_contact(lower, upper, 0.01,
                          {gap, world_direction(Eigen::Vector3d::UnitZ()), world({0, 0, 0}),
                           world({0, 0, gap})},
                          kFcl);
  }
}

TEST(BoxBoxManifold, PlanarRectanglesGiveTwoPoints) {
  // Plane scenes: the boxes' z = 0 sections. A rectangle on a wider one: its two bottom corners; moved
  // past the lower one's end: its inner corner and the lower one's end corner.
  const Placed lower{Box{{1.0, 0.5, 0.3}}, translation(0.0, -0.5, 0.0), true};
  for (double x : {0.2, 0.9}) {
    SCOPED_TRACE(x);
    const Placed upper{Box{{0.3, 0.2, 0.3}}, translation(x, 0.2 + 0.001, 0.0)};
    for (bool reversed : {false, true}) {
      auto contacts = detect(lower, upper, 0.01, reversed, /*planar=*/true);
      ASSERT_EQ(contacts.size(), 2u);
      std::vector<double> xs;
      for (ContactPoint& c : contacts) {
        if (reversed) std::swap(c.point_a, c.point_b);
        EXPECT_NEAR(c.gap, 0.001, kExact);
        EXPECT_NEAR(c.point_b.y(), 0.001, kExact);
        EXPECT_NEAR(c.point_a.y(), 0.0, kExact);
        EXPECT_EQ(c.point_a.z(), 0.0);
        xs.push_back(c.point_b.x());
      }
      std::sort(xs.begin(), xs.end());
      EXPECT_NEAR(xs[0], x - 0.3, kExact);
      EXPECT_NEAR(xs[1], std::min(x + 0.3, 1.0), kExact);
    }
  }
}

}  // namespace
}  // namespace csim
