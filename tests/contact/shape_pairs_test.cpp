// Capsule, cylinder and convex hull pairs (contact/gjk_pairs.h, contact/halfspace_pairs.h; their
// manifolds against faces and parallel segments in convex_manifold_test.cpp) and the
// hull construction (contact/convex_hull.h), each against a closed form. Tolerances: 1e-12 m for the
// closed-form halfspace manifolds; for the FCL-backed pairs 1e-9 m on gaps and points, and on normals
// 1e-9 where a face takes part, 1e-5 between two curved surfaces (GJK's witness direction there is
// good to the square root of its distance tolerance, gjk_pairs.h).
#include "contact/collision_world.h"
#include "contact/convex_hull.h"
#include "contact/halfspace_pairs.h"
#include "contact/narrow_phase.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace csim {
namespace {

constexpr double kExact = 1e-12;   // m, closed forms
constexpr double kFcl = 1e-9;      // m, FCL's GJK at a distance tolerance of 1e-12
constexpr double kCurved = 1e-5;   // normal between two curved surfaces (dimensionless)
constexpr double kPi = 3.14159265358979323846;

Eigen::Isometry3d translation(const Eigen::Vector3d& x) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = x;
  return pose;
}

Eigen::Isometry3d rotation(double angle, const Eigen::Vector3d& axis) {
  return Eigen::Isometry3d(Eigen::AngleAxisd(angle, axis.normalized()));
}

// A generic rigid motion applied to whole scenes so that no test relies on world axes.
const Eigen::Isometry3d kScene = translation({0.3, -0.7, 1.1}) * rotation(0.7, {1, 2, 3});
// Turns a shape's local z onto the scene's x (a capsule or cylinder lying along x).
const Eigen::Isometry3d kAlongX = rotation(kPi / 2, {0, 1, 0});

void expect_near(const Eigen::Vector3d& actual, const Eigen::Vector3d& expected, double tol) {
  EXPECT_LE((actual - expected).norm(), tol) << "actual   " << actual.transpose()
                                             << "\nexpected " << expected.transpose();
}

struct Placed {
  Shape shape;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  bool fixed = false;
};

// Detects between `first` (object 0 unless reversed) and `second`, and checks the conventions of
// contact_point.h that hold for every contact.
std::vector<ContactPoint> detect(const Placed& first, const Placed& second, double margin, bool reversed = false) {
  CollisionWorld world(false);
  const Placed& x = reversed ? second : first;
  const Placed& y = reversed ? first : second;
  world.set_pose(world.add_object(0, x.shape, x.fixed), x.pose);
  world.set_pose(world.add_object(1, y.shape, y.fixed), y.pose);
  world.update(margin);
  std::vector<ContactPoint> contacts;
  world.find_contacts(contacts);
  for (const ContactPoint& c : contacts) {
    EXPECT_NEAR(c.normal.norm(), 1.0, 1e-12);
    expect_near(c.point_b - c.point_a, c.gap * c.normal, 1e-9);
  }
  return contacts;
}

// One contact, normal from first to second, in both registration orders.
void expect_single_contact(const Placed& first, const Placed& second, double margin, double gap,
                           const Eigen::Vector3d& normal, double normal_tolerance,
                           const Eigen::Vector3d* on_first = nullptr, const Eigen::Vector3d* on_second = nullptr) {
  for (bool reversed : {false, true}) {
    SCOPED_TRACE(reversed ? "ids swapped" : "ids in order");
    const auto contacts = detect(first, second, margin, reversed);
    ASSERT_EQ(contacts.size(), 1u);
    const ContactPoint& c = contacts[0];
    EXPECT_NEAR(c.gap, gap, kFcl);
    expect_near(reversed ? Eigen::Vector3d(-c.normal) : c.normal, normal, normal_tolerance);
    if (on_first) expect_near(reversed ? c.point_b : c.point_a, *on_first, kFcl);
    if (on_second) expect_near(reversed ? c.point_a : c.point_b, *on_second, kFcl);
  }
}

void expect_no_contact(const Placed& first, const Placed& second, double margin) {
  EXPECT_TRUE(detect(first, second, margin, false).empty());
  EXPECT_TRUE(detect(first, second, margin, true).empty());
}

// The gaps a pair is checked at: separated, at GJK's touching threshold, touching, overlapping.
const double kGaps[] = {0.05, 2e-6, 5e-7, 1e-10, 0.0, -1e-7, -1e-3};

// ---------------------------------------------------------------------------------------------------
// capsule–halfspace, cylinder–halfspace, convex–halfspace (closed forms)

const Placed kIncline{Halfspace{Eigen::Vector3d::UnitZ(), 0.1},
                      translation({0.3, -0.2, 0.05}) * rotation(20.0 * kPi / 180.0, {0, 1, 0}), true};
const Eigen::Vector3d kUp = kIncline.pose.linear() * Eigen::Vector3d::UnitZ();

// Height above the inclined plane of a world point.
double height(const Eigen::Vector3d& x) { return kUp.dot(x - kIncline.pose.translation()) - 0.1; }

TEST(CapsuleHalfspace, LyingGivesBothCapsWithExactGaps) {
  const Capsule capsule{0.2, 0.5};
  for (double gap : {0.05, 0.0, -0.01}) {
    SCOPED_TRACE(gap);
    // Axis along the plane's x, at 0.2 + gap above it.
    const Placed lying{capsule, kIncline.pose * translation({0.4, 0.1, 0.1 + 0.2 + gap}) * kAlongX};
    const auto contacts = detect(lying, kIncline, 0.1);
    ASSERT_EQ(contacts.size(), 2u);
    for (int end = 0; end < 2; ++end) {
      const ContactPoint& c = contacts[end];
      EXPECT_EQ(c.key, (ContactKey{0, 1, end}));
      EXPECT_NEAR(c.gap, gap, kExact);
      expect_near(c.normal, -kUp, kExact);
      const Eigen::Vector3d cap = lying.pose * Eigen::Vector3d(0, 0, end == 0 ? -0.5 : 0.5);
      expect_near(c.point_a, cap - 0.2 * kUp, kExact);
      EXPECT_FALSE(c.has_arm_a());  // the lowest point rolls over the cap
    }
  }
}

TEST(CapsuleHalfspace, TiltedGivesEachCapItsOwnGapAndDropsThoseBeyondTheMargin) {
  const Capsule capsule{0.2, 0.5};
  const Placed tilted{capsule, kIncline.pose * translation({0.4, 0.1, 0.1 + 0.5}) * rotation(1.2, {1, 0.3, 0})};
  const double gaps[2] = {height(tilted.pose * Eigen::Vector3d(0, 0, -0.5)) - 0.2,
                          height(tilted.pose * Eigen::Vector3d(0, 0, 0.5)) - 0.2};
  const auto all = detect(tilted, kIncline, 10.0);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_NEAR(all[0].gap, gaps[0], kExact);
  EXPECT_NEAR(all[1].gap, gaps[1], kExact);
  const double margin = 0.5 * (gaps[0] + gaps[1]);  // between them: only the lower cap
  const auto lower = detect(tilted, kIncline, margin);
  ASSERT_EQ(lower.size(), 1u);
  EXPECT_EQ(lower[0].key.feature, gaps[0] < gaps[1] ? 0 : 1);
}

TEST(CylinderHalfspace, StandingGivesTheBottomRimPointsWithTheirArms) {
  const Cylinder cylinder{0.3, 0.4};
  for (double gap : {0.05, 0.0, -0.01}) {
    SCOPED_TRACE(gap);
    const Placed standing{cylinder, kIncline.pose * translation({0.4, 0.1, 0.1 + 0.4 + gap}) * rotation(0.3, {0, 0, 1})};
    const auto contacts = detect(standing, kIncline, 0.1);
    ASSERT_EQ(contacts.size(), static_cast<std::size_t>(kRimPoints));  // the top rim is 0.8 m higher
    for (int j = 0; j < kRimPoints; ++j) {
      const ContactPoint& c = contacts[j];
      EXPECT_EQ(c.key.feature, j);
      EXPECT_NEAR(c.gap, gap, kExact);
      const Eigen::Vector3d r = cylinder_rim_point(cylinder, 0, j);
      EXPECT_NEAR(r.head<2>().norm(), 0.3, kExact);
      ASSERT_TRUE(c.has_arm_a());
      expect_near(c.arm_a, standing.pose.linear() * r, kExact);
      expect_near(c.point_a, standing.pose * r, kExact);
    }
  }
}

TEST(CylinderHalfspace, LyingRestsOnItsLowestGenerator) {
  const Cylinder cylinder{0.3, 0.4};
  // Rolled 0.2 rad about its axis; a margin that holds the rim points nearest the bottom, which are
  // not reported: the axis lies across the normal (halfspace_pairs.h).
  const Placed lying{cylinder, kIncline.pose * translation({0.4, 0.1, 0.1 + 0.3}) * kAlongX * rotation(0.2, {0, 0, 1})};
  const double margin = 0.05;
  ASSERT_LE(height(lying.pose * cylinder_rim_point(cylinder, 0, 0)), margin);
  const auto contacts = detect(lying, kIncline, margin);
  ASSERT_EQ(contacts.size(), 2u);
  for (int rim = 0; rim < 2; ++rim) {
    const ContactPoint& lowest = contacts[rim];
    EXPECT_EQ(lowest.key.feature, 2 * kRimPoints + rim);
    EXPECT_NEAR(lowest.gap, 0.0, kExact);
    expect_near(lowest.point_a, lying.pose * Eigen::Vector3d(0, 0, rim == 0 ? -0.4 : 0.4) - 0.3 * kUp, kExact);
    EXPECT_FALSE(lowest.has_arm_a());
  }
}

TEST(CylinderHalfspace, TiltedOnItsEdge) {
  // Axis tilted θ from the plane's normal: the lowest rim point is h cos θ + r sin θ below the centre.
  const Cylinder cylinder{0.3, 0.4};
  const double theta = 0.5, lift = 0.02;
  const double centre = 0.4 * std::cos(theta) + 0.3 * std::sin(theta) + lift;
  const Placed tilted{cylinder, kIncline.pose * translation({0.4, 0.1, 0.1 + centre}) * rotation(theta, {0, 1, 0})};
  const double margin = 0.1;
  const auto contacts = detect(tilted, kIncline, margin);
  std::vector<int> expected;  // the axis is 0.5 rad from the normal: rim points, then the lowest point
  for (int rim = 0; rim < 2; ++rim)
    for (int j = 0; j < kRimPoints; ++j)
      if (height(tilted.pose * cylinder_rim_point(cylinder, rim, j)) <= margin) expected.push_back(kRimPoints * rim + j);
  expected.push_back(2 * kRimPoints);
  std::vector<int> reported;
  for (const ContactPoint& c : contacts) reported.push_back(c.key.feature);
  EXPECT_EQ(reported, expected);
  const ContactPoint& lowest = contacts.back();
  EXPECT_NEAR(lowest.gap, lift, kExact);
  for (const ContactPoint& c : contacts) {
    EXPECT_GE(c.gap, lift - kExact);
    EXPECT_NEAR(c.gap, height(c.point_a), kExact);
  }
}

// A regular tetrahedron: its centroid at the origin, its lowest face 1/3 of its height below it.
std::vector<Eigen::Vector3d> tetrahedron_points() {
  return {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
}

TEST(ConvexHalfspace, TetrahedronGivesEveryVertexWithinTheMarginWithItsArm) {
  const Convex hull = make_convex(tetrahedron_points());
  const Placed tetra{hull, kIncline.pose * translation({0.4, 0.1, 1.0}) * rotation(0.8, {1, 2, -1})};
  for (double margin : {10.0, 0.9}) {
    SCOPED_TRACE(margin);
    std::vector<int> expected;
    for (int i = 0; i < 4; ++i)
      if (height(tetra.pose * hull.vertices[i]) <= margin) expected.push_back(i);
    const auto contacts = detect(tetra, kIncline, margin);
    std::vector<int> reported;
    for (const ContactPoint& c : contacts) {
      reported.push_back(c.key.feature);
      const Eigen::Vector3d vertex = tetra.pose * hull.vertices[c.key.feature];
      EXPECT_NEAR(c.gap, height(vertex), kExact);
      expect_near(c.point_a, vertex, kExact);
      expect_near(c.arm_a, tetra.pose.linear() * hull.vertices[c.key.feature], kExact);
    }
    EXPECT_EQ(reported, expected);
    if (margin < 1.0) {
      EXPECT_LT(expected.size(), 4u);
    }
  }
}

TEST(ConvexHalfspace, CubeAgreesWithBox) {
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i) corners.push_back(box_vertex(Box{{0.5, 0.4, 0.3}}, i, false));
  const Convex cube = make_convex(corners);
  ASSERT_EQ(cube.vertices.size(), 8u);  // kept in the order given: feature i is box vertex i
  const Eigen::Isometry3d pose = kIncline.pose * translation({0.4, 0.1, 0.1 + 0.5}) * rotation(0.4, {1, -1, 0.2});
  const auto as_box = detect({Box{{0.5, 0.4, 0.3}}, pose}, kIncline, 0.2);
  const auto as_hull = detect({cube, pose}, kIncline, 0.2);
  ASSERT_EQ(as_box.size(), as_hull.size());
  ASSERT_FALSE(as_box.empty());
  for (std::size_t k = 0; k < as_box.size(); ++k) {
    EXPECT_EQ(as_box[k].key, as_hull[k].key);
    EXPECT_NEAR(as_box[k].gap, as_hull[k].gap, kExact);
    expect_near(as_box[k].arm_a, as_hull[k].arm_a, kExact);
  }
}

// ---------------------------------------------------------------------------------------------------
// FCL-backed pairs

TEST(SphereCapsule, BesideTheSideAndBeyondACap) {
  const Placed capsule{Capsule{0.2, 0.5}, kScene};
  const Eigen::Vector3d side = kScene.linear() * Eigen::Vector3d(0.6, 0.8, 0).normalized();
  const Eigen::Vector3d tip = kScene.linear() * Eigen::Vector3d::UnitZ();
  for (double gap : kGaps) {
    SCOPED_TRACE(gap);
    // Beside the cylindrical part at z = 0.3: normal from the sphere to the capsule is −side.
    const Eigen::Vector3d axis_point = kScene * Eigen::Vector3d(0, 0, 0.3);
    const Eigen::Vector3d c1 = axis_point + (0.2 + 0.1 + gap) * side;
    Eigen::Vector3d on_sphere = c1 - 0.1 * side, on_capsule = axis_point + 0.2 * side;
    expect_single_contact({Sphere{0.1}, translation(c1)}, capsule, 0.1, gap, -side, kFcl, &on_sphere, &on_capsule);
    // Beyond the +z cap, off its axis.
    const Eigen::Vector3d cap = kScene * Eigen::Vector3d(0, 0, 0.5);
    const Eigen::Vector3d u = (tip + 0.5 * side).normalized();
    const Eigen::Vector3d c2 = cap + (0.2 + 0.1 + gap) * u;
    on_sphere = c2 - 0.1 * u, on_capsule = cap + 0.2 * u;
    expect_single_contact({Sphere{0.1}, translation(c2)}, capsule, 0.1, gap, -u, kFcl, &on_sphere, &on_capsule);
  }
  expect_no_contact({Sphere{0.1}, translation(kScene * Eigen::Vector3d(0, 0, 0.5 + 0.2 + 0.1 + 0.11))}, capsule, 0.1);
}

TEST(CapsuleCapsule, Crossing) {
  // Parallel capsules touch along a segment: convex_manifold_test.cpp.
  const Placed a{Capsule{0.2, 0.5}, kScene * kAlongX};
  const Eigen::Vector3d ez = kScene.linear() * Eigen::Vector3d::UnitZ();
  for (double gap : kGaps) {
    SCOPED_TRACE(gap);
    // Overlapping, the translation starts from MPR's normal, off by 5e-4 between curved surfaces.
    const double tolerance = gap < 0.0 ? kCurved : kFcl;
    // Crossing at right angles, one above the other along z: closest points on the two axes at
    // (0.1, 0, 0) and (0.1, 0, 0.35 + gap).
    const Placed crossing{Capsule{0.15, 0.35}, kScene * translation({0.1, 0.2, 0.35 + gap}) * rotation(kPi / 2, {1, 0, 0})};
    const Eigen::Vector3d on_a = kScene * Eigen::Vector3d(0.1, 0.0, 0.2);
    const Eigen::Vector3d on_b = kScene * Eigen::Vector3d(0.1, 0.0, 0.2 + gap);
    expect_single_contact(a, crossing, 0.1, gap, ez, tolerance, gap < 0.0 ? nullptr : &on_a, gap < 0.0 ? nullptr : &on_b);
  }
  expect_no_contact(a, {Capsule{0.15, 0.35}, kScene * translation({0.1, 0.2, 0.35 + 0.11}) * rotation(kPi / 2, {1, 0, 0})}, 0.1);
}

// A capsule or cylinder lying or standing on a box: convex_manifold_test.cpp.

TEST(SphereCylinder, AboveTheFaceAndBesideTheSide) {
  const Placed cylinder{Cylinder{0.3, 0.4}, kScene};
  const Eigen::Vector3d ez = kScene.linear() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d side = kScene.linear() * Eigen::Vector3d(0.8, -0.6, 0);
  for (double gap : kGaps) {
    SCOPED_TRACE(gap);
    expect_single_contact(cylinder, {Sphere{0.1}, kScene * translation({0.1, 0.1, 0.4 + 0.1 + gap})}, 0.1, gap, ez, kFcl);
    expect_single_contact(cylinder, {Sphere{0.1}, translation(kScene * Eigen::Vector3d(0, 0, 0.2) + (0.4 + gap) * side)},
                          0.1, gap, side, kFcl);
  }
}

TEST(CylinderCapsule, SideBySide) {
  // Both upright, axes 0.3 + 0.2 + gap apart: a line contact along their sides, two points (the
  // capsule's core, 0.6 long, is the shorter segment: the incident one), at its ends' heights.
  const Placed cylinder{Cylinder{0.3, 0.4}, kScene};
  const Eigen::Vector3d ey = kScene.linear() * Eigen::Vector3d::UnitY();
  for (double gap : kGaps) {
    SCOPED_TRACE(gap);
    for (bool reversed : {false, true}) {
      const auto contacts = detect(cylinder, {Capsule{0.2, 0.3}, kScene * translation({0, 0.5 + gap, 0.1})}, 0.1, reversed);
      ASSERT_EQ(contacts.size(), 2u);
      std::vector<double> heights;
      for (const ContactPoint& c : contacts) {
        EXPECT_NEAR(c.gap, gap, kCurved);
        expect_near(reversed ? Eigen::Vector3d(-c.normal) : c.normal, ey, kCurved);
        heights.push_back((kScene.inverse() * c.point_a).z());
      }
      std::sort(heights.begin(), heights.end());
      EXPECT_NEAR(heights[0], 0.1 - 0.3, kCurved);
      EXPECT_NEAR(heights[1], 0.1 + 0.3, kCurved);
    }
  }
}

// A cylinder standing on another's cap: convex_manifold_test.cpp.

TEST(ConvexPairs, CubeAgreesWithBoxAgainstASphereAndACapsule) {
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i) corners.push_back(box_vertex(Box{{0.5, 0.4, 0.3}}, i, false));
  const Placed hull{make_convex(corners), kScene};
  const Placed box{Box{{0.5, 0.4, 0.3}}, kScene};
  const Eigen::Vector3d ex = kScene.linear() * Eigen::Vector3d::UnitX();
  for (double gap : kGaps) {
    SCOPED_TRACE(gap);
    const Placed sphere{Sphere{0.2}, kScene * translation({0.5 + 0.2 + gap, 0.1, -0.1})};
    const ContactPoint with_box = detect(box, sphere, 0.1).at(0);
    expect_single_contact(hull, sphere, 0.1, with_box.gap, ex, kFcl);
    EXPECT_NEAR(with_box.gap, gap, kFcl);
    // A capsule lying across the face: two points, as on the box.
    const Placed capsule{Capsule{0.1, 0.2}, kScene * translation({0.5 + 0.1 + gap, 0.0, 0.0}) * rotation(0.3, {1, 0, 0})};
    const auto on_box = detect(box, capsule, 0.1);
    const auto on_hull = detect(hull, capsule, 0.1);
    ASSERT_EQ(on_box.size(), 2u);
    ASSERT_EQ(on_hull.size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) {
      EXPECT_NEAR(on_hull[k].gap, gap, kExact);
      EXPECT_NEAR(on_box[k].gap, gap, kExact);
      expect_near(on_hull[k].normal, ex, kExact);
      expect_near(on_hull[k].point_b, on_box[k].point_b, kExact);
    }
  }
}

TEST(ConvexPairs, TetrahedronOnABoxFace) {
  // A regular tetrahedron with one vertex down (along −z) above a box's top face: the gap is the
  // vertex's height above the face.
  std::vector<Eigen::Vector3d> points = tetrahedron_points();
  const Eigen::Vector3d down = Eigen::Vector3d(1, 1, 1).normalized();  // vertex 0's direction
  const Eigen::Isometry3d turn = rotation(std::acos(-down.z()), down.cross(-Eigen::Vector3d::UnitZ()));
  const Placed box{Box{{1.0, 1.0, 0.5}}, kScene};
  const Eigen::Vector3d ez = kScene.linear() * Eigen::Vector3d::UnitZ();
  for (double gap : kGaps) {
    SCOPED_TRACE(gap);
    const Placed tetra{make_convex(points), kScene * translation({0.1, 0.2, 0.5 + std::sqrt(3.0) + gap}) * turn};
    const Eigen::Vector3d vertex = kScene * Eigen::Vector3d(0.1, 0.2, 0.5 + gap);
    expect_single_contact(box, tetra, 0.1, gap, ez, kFcl, nullptr, &vertex);
  }
}

// ---------------------------------------------------------------------------------------------------
// shapes against a triangle mesh (contact/mesh_pairs.h)

// The square [−1, 1]² of z = 0 in two triangles split along the diagonal y = x, counter-clockwise
// seen from +z: triangle 0 below the diagonal (y < x), triangle 1 above it. Placed on the incline.
const Placed kTerrain{TriangleMesh{{{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, {{{0, 1, 2}}, {{0, 2, 3}}}},
                      kIncline.pose, true};

// Height above the terrain's plane (the incline's local z = 0, not its offset 0.1).
double terrain_height(const Eigen::Vector3d& x) { return kUp.dot(x - kIncline.pose.translation()); }

TEST(MeshPairs, SphereAboveATriangle) {
  for (double gap : {0.05, 1e-10, 0.0, -0.01}) {
    SCOPED_TRACE(gap);
    const Eigen::Vector3d centre = kIncline.pose * Eigen::Vector3d(0.5, -0.5, 0.1 + gap);
    const Placed sphere{Sphere{0.1}, translation(centre)};
    const auto contacts = detect(sphere, kTerrain, 0.1);
    ASSERT_EQ(contacts.size(), 1u);  // 0.7 m from the diagonal: triangle 0 only, its closest points
    EXPECT_EQ(contacts[0].key.feature, 0);
    EXPECT_NEAR(contacts[0].gap, gap, kFcl);
    expect_near(contacts[0].normal, -kUp, kFcl);
    // GJK's witness on the sphere's curved support (the triangle has no closed form in FCL): to
    // √(tolerance · r) ≈ 3e-7 m along the surface.
    expect_near(contacts[0].point_a, centre - 0.1 * kUp, 1e-6);
  }
  expect_no_contact({Sphere{0.1}, translation(kIncline.pose * Eigen::Vector3d(0.5, -0.5, 0.1 + 0.11))}, kTerrain, 0.1);
}

TEST(MeshPairs, BoxRestsOnItsBottomVerticesAcrossBothTriangles) {
  // A box turned 0.3 rad about the normal over the diagonal: its bottom vertices fall in either
  // triangle; each is reported once, in the triangle it projects into, with its exact gap and arm.
  const Box shape{{0.3, 0.2, 0.1}};
  constexpr int K = 8 + 1;  // feature points per triangle, and the closest points
  for (double gap : {0.02, 0.0, -0.005}) {
    SCOPED_TRACE(gap);
    const Placed box{shape, kIncline.pose * translation({0.1, 0.05, 0.1 + gap}) * rotation(0.3, {0, 0, 1})};
    std::vector<int> expected;
    for (int t = 0; t < 2; ++t)
      for (int i = 0; i < 4; ++i) {
        const Eigen::Vector3d local = kIncline.pose.inverse() * (box.pose * box_vertex(shape, i, false));
        if ((local.y() < local.x()) == (t == 0)) expected.push_back(t * K + i);
      }
    ASSERT_EQ(expected.size(), 4u);
    ASSERT_LT(expected[0], K);  // the diagonal splits them
    ASSERT_GE(expected[3], K);
    std::vector<int> vertices;
    int closest = 0;
    for (const ContactPoint& c : detect(box, kTerrain, 0.05)) {
      if (c.key.feature % K == K - 1) {  // the closest points of the box and the triangle
        ++closest;
        EXPECT_NEAR(c.gap, gap, kFcl);
        continue;
      }
      vertices.push_back(c.key.feature);
      const int i = c.key.feature % K;
      const Eigen::Vector3d vertex = box.pose * box_vertex(shape, i, false);
      EXPECT_NEAR(c.gap, terrain_height(vertex), kExact);
      EXPECT_NEAR(c.gap, gap, kExact);
      expect_near(c.arm_a, box.pose.linear() * box_vertex(shape, i, false), kExact);
      expect_near(c.normal, -kUp, kExact);
    }
    EXPECT_EQ(vertices, expected);
    EXPECT_EQ(closest, 2);
  }
}

TEST(MeshPairs, CapsuleLyingGivesItsCapsWithExactGaps) {
  constexpr int K = 2 + 1;
  const Placed lying{Capsule{0.1, 0.3}, kIncline.pose * translation({0.5, -0.6, 0.1 + 0.01}) * kAlongX};
  std::vector<int> caps;
  for (const ContactPoint& c : detect(lying, kTerrain, 0.05)) {
    EXPECT_NEAR(c.gap, 0.01, c.key.feature % K == K - 1 ? kFcl : kExact);
    if (c.key.feature % K < K - 1) caps.push_back(c.key.feature);
  }
  EXPECT_EQ(caps, (std::vector<int>{0, 1}));  // both caps over triangle 0
}

TEST(MeshPairs, AMeshOnlyOnAFixedBody) {
  CollisionWorld world(false);
  EXPECT_THROW(world.add_object(0, kTerrain.shape, false), std::invalid_argument);
  EXPECT_THROW(world.add_object(0, TriangleMesh{{{0, 0, 0}}, {{{0, 1, 2}}}}, true), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------------
// broad phase and set-up

TEST(ShapeBounds, TiltedCylinderRimReachesASphere) {
  // A cylinder tilted 45° about y: its rim reaches x = h sin 45° + r cos 45°; a sphere just beyond
  // must reach the narrow phase (the world box of the shape must hold the rim).
  const double h = 0.4, r = 0.3, reach = (h + r) * std::sqrt(0.5);
  const Placed cylinder{Cylinder{r, h}, rotation(kPi / 4, {0, 1, 0})};
  const Placed sphere{Sphere{0.05}, translation({reach + 0.05 + 0.01, 0, 0.4 * std::sqrt(0.5) - 0.3 * std::sqrt(0.5)})};
  const auto contacts = detect(cylinder, sphere, 0.02);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_NEAR(contacts[0].gap, 0.01, kFcl);
}

TEST(ShapeBounds, PlaneWorldsRefuseTheThreeDimensionalShapes) {
  CollisionWorld planar(true);
  EXPECT_THROW(planar.add_object(0, Capsule{0.1, 0.2}, false), std::invalid_argument);
  EXPECT_THROW(planar.add_object(0, Cylinder{0.1, 0.2}, false), std::invalid_argument);
  EXPECT_THROW(planar.add_object(0, make_convex(tetrahedron_points()), false), std::invalid_argument);
  CollisionWorld space(false);
  EXPECT_THROW(space.add_object(0, Cylinder{0.1, 0.0}, false), std::invalid_argument);
  EXPECT_THROW(space.add_object(0, Capsule{0.0, 0.2}, false), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------------
// convex hull construction and mass properties

TEST(ConvexHull, CubeWithInteriorPointsKeepsItsCornersAndHasTheCubesMassProperties) {
  // A 1 × 0.8 × 0.6 box's corners, points inside it and on its faces, shifted by c.
  const Eigen::Vector3d c(0.3, -0.2, 0.1);
  std::vector<Eigen::Vector3d> points = {c, c + Eigen::Vector3d(0.1, 0.1, 0.1), c + Eigen::Vector3d(0.5, 0.0, 0.0),
                                         c + Eigen::Vector3d(0.2, 0.4, 0.1)};
  for (int i = 0; i < 8; ++i) points.push_back(c + box_vertex(Box{{0.5, 0.4, 0.3}}, i, false));
  const Convex hull = make_convex(points);
  ASSERT_EQ(hull.vertices.size(), 8u);
  for (int i = 0; i < 8; ++i) expect_near(hull.vertices[i], points[4 + i], 0.0);
  EXPECT_EQ(hull.faces.size(), 12u);  // 6 faces, 2 triangles each
  const ConvexMassProperties m = convex_mass_properties(hull);
  EXPECT_NEAR(m.volume, 1.0 * 0.8 * 0.6, 1e-14);
  expect_near(m.centroid, c, 1e-14);
  // Per unit density: V (b² + c²)/12, ... for sides a, b, c.
  const double V = 0.48;
  const Eigen::Vector3d expected(V * (0.64 + 0.36) / 12, V * (1.0 + 0.36) / 12, V * (1.0 + 0.64) / 12);
  EXPECT_LE((m.inertia_per_density - Eigen::Matrix3d(expected.asDiagonal())).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(ConvexHull, CubesPolygonsAreItsSixFacesAndItsEdgesTwelve) {
  // make_convex merges each face's two triangles: 6 quadrilaterals, each with the outward axis as
  // normal, the product of its two sides as area, its corners counter-clockwise seen from outside;
  // 12 edges, 4 along each axis, of the side's length.
  const Eigen::Vector3d h(0.5, 0.4, 0.3);
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i) corners.push_back(box_vertex(Box{h}, i, false));
  const Convex hull = make_convex(corners);
  ASSERT_EQ(hull.polygons.size(), 6u);
  std::vector<bool> seen(6, false);
  for (const ConvexFace& face : hull.polygons) {
    ASSERT_EQ(face.vertices.size(), 4u);
    int axis = 0;
    face.normal.cwiseAbs().maxCoeff(&axis);
    const double sign = face.normal[axis] > 0.0 ? 1.0 : -1.0;
    expect_near(face.normal, sign * Eigen::Vector3d::Unit(axis), 1e-15);
    seen[2 * axis + (sign > 0.0 ? 1 : 0)] = true;
    EXPECT_NEAR(face.area, 4.0 * h[(axis + 1) % 3] * h[(axis + 2) % 3], 1e-15);
    for (std::size_t k = 0; k < 4; ++k) {
      const Eigen::Vector3d& a = hull.vertices[face.vertices[k]];
      const Eigen::Vector3d& b = hull.vertices[face.vertices[(k + 1) % 4]];
      const Eigen::Vector3d& c = hull.vertices[face.vertices[(k + 2) % 4]];
      EXPECT_NEAR(a[axis], sign * h[axis], 1e-15);              // on the face
      EXPECT_GT((b - a).cross(c - b).dot(face.normal), 0.0);   // counter-clockwise from outside
    }
  }
  EXPECT_EQ(seen, std::vector<bool>(6, true));
  ASSERT_EQ(hull.edges.size(), 12u);
  Eigen::Vector3i along = Eigen::Vector3i::Zero();
  for (const auto& edge : hull.edges) {
    EXPECT_LT(edge[0], edge[1]);
    const Eigen::Vector3d d = (hull.vertices[edge[1]] - hull.vertices[edge[0]]).cwiseAbs();
    int axis = 0;
    d.maxCoeff(&axis);
    EXPECT_NEAR(d[axis], 2.0 * h[axis], 1e-15);
    EXPECT_NEAR(d.sum(), d[axis], 1e-15);  // along one axis
    ++along[axis];
  }
  EXPECT_EQ(along, Eigen::Vector3i(4, 4, 4));
}

TEST(ConvexHull, FacesAreOutwardAndEveryPointIsInside) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 60; ++i) {  // a deterministic scatter: points of a sphere and inside it
    const double t = 0.37 * i, p = 0.11 * i * i;
    const double radius = i % 3 == 0 ? 0.5 : 1.0;
    points.emplace_back(radius * std::sin(t) * std::cos(p), radius * std::sin(t) * std::sin(p), radius * std::cos(t));
  }
  const Convex hull = make_convex(points);
  for (const auto& f : hull.faces) {
    const Eigen::Vector3d n = (hull.vertices[f[1]] - hull.vertices[f[0]]).cross(hull.vertices[f[2]] - hull.vertices[f[0]]);
    for (const Eigen::Vector3d& x : points) EXPECT_LE(n.normalized().dot(x - hull.vertices[f[0]]), 1e-9);
  }
  // A closed surface: Euler's V − E + F = 2 with E = 3F/2; and for the polygons and edges kept.
  EXPECT_EQ(static_cast<int>(hull.vertices.size()) - static_cast<int>(hull.faces.size()) / 2, 2);
  EXPECT_EQ(static_cast<int>(hull.vertices.size()) - static_cast<int>(hull.edges.size()) +
                static_cast<int>(hull.polygons.size()),
            2);
  EXPECT_GT(convex_mass_properties(hull).volume, 0.0);
}

TEST(ConvexHull, TetrahedronVolumeAndRefusals) {
  const ConvexMassProperties m = convex_mass_properties(make_convex(tetrahedron_points()));
  EXPECT_NEAR(m.volume, 8.0 / 3.0, 1e-14);  // a cube of side 2 less four corners of 4/3 each
  expect_near(m.centroid, Eigen::Vector3d::Zero(), 1e-15);
  EXPECT_THROW(make_convex({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), std::invalid_argument);
  EXPECT_THROW(make_convex({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.5, 0}}), std::invalid_argument);
  EXPECT_THROW(make_convex({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}}), std::invalid_argument);
}

}  // namespace
}  // namespace csim
