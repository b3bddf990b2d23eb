// Manifolds of the convex pairs other than box–box (contact/convex_manifold.h) through CollisionWorld,
// against closed forms: the points of a shape resting on a face are its feature's points over that
// face, each at its height above it; two parallel capsules, or a box's edge and a parallel capsule's
// core or cylinder's side, touch along the overlap of the two segments.
// Tolerances: kExact (1e-12 m) where the normal is a face normal (the gaps are then heights of
// points); kFcl (1e-9 m) where FCL's normal enters (two parallel segments), kCurved (1e-5) for that
// normal when the capsules overlap (the penetration query's start, gjk_pairs.h).
#include "contact/convex_hull.h"
#include "contact/halfspace_pairs.h"
#include "contact/narrow_phase.h"
#include "tests/contact/detection_test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace csim {
namespace {

using namespace detection_test;

constexpr double kCurved = 1e-5;
// Separated, at GJK's touching threshold, touching, overlapping (gjk_pairs.h).
const double kGaps[] = {0.05, 2e-6, 5e-7, 1e-10, 0.0, -1e-7, -1e-3};

Eigen::Vector3d local(const Eigen::Vector3d& world_point) { return kScene.inverse() * world_point; }
const Eigen::Vector3d kUp = kScene.linear() * Eigen::Vector3d::UnitZ();

Placed at(const Shape& shape, const Eigen::Vector3d& centre, const Eigen::Isometry3d& turn = Eigen::Isometry3d::Identity()) {
  return {shape, kScene * translation(centre.x(), centre.y(), centre.z()) * turn};
}

// The lower body: a slab whose top face is the local plane z = 0.
const Placed kSlab = at(Box{{1.0, 0.8, 0.5}}, {0.0, 0.0, -0.5});
const Eigen::Isometry3d kAlongX = rotation(kPi / 2, {0, 1, 0});  // a shape's z onto the local x

// The contacts of `upper` on the slab (slab registered first unless `reversed`), with the upper
// shape's point, arm and feature as seen from the slab (A) side.
struct OnSlab {
  Eigen::Vector3d upper_point;  // local frame
  Eigen::Vector3d upper_arm;    // world; NaN where not material
  int feature;
  double gap;
};

std::vector<OnSlab> on_slab(const Placed& upper, double margin, bool reversed) {
  std::vector<OnSlab> result;
  for (const ContactPoint& c : detect(kSlab, upper, margin, reversed)) {
    // The slab is object 0: A unless reversed. The normal from the slab up is +z of the local frame.
    const Eigen::Vector3d up = reversed ? Eigen::Vector3d(-c.normal) : c.normal;
    expect_near(up, kUp, kExact);
    const Eigen::Vector3d on_slab = reversed ? c.point_b : c.point_a;
    EXPECT_NEAR(local(on_slab).z(), 0.0, kExact);  // on the top face
    result.push_back({local(reversed ? c.point_a : c.point_b), reversed ? c.arm_a : c.arm_b, c.key.feature, c.gap});
  }
  return result;
}

double polygon_area(std::vector<Eigen::Vector3d> points) {  // of points in convex position, local xy
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p / static_cast<double>(points.size());
  std::sort(points.begin(), points.end(), [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::atan2(a.y() - mean.y(), a.x() - mean.x()) < std::atan2(b.y() - mean.y(), b.x() - mean.x());
  });
  double area = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d& p = points[i];
    const Eigen::Vector3d& q = points[(i + 1) % points.size()];
    area += 0.5 * (p.x() * q.y() - p.y() * q.x());
  }
  return area;
}

TEST(ConvexManifold, CylinderStandingOnABoxRestsOnFourRimPoints) {
  // Radius 0.3, half length 0.4, turned 0.25 rad about its axis, centre 0.4 + gap above the face:
  // its bottom rim's 8 points (halfspace_pairs.h) all lie over the face at height gap; the 4 kept are
  // alternate ones (rim points 0, 2, 4, 6: the deepest on a tie is the first, then those spanning the
  // largest area), a square of area 2 r².
  const Cylinder cylinder{0.3, 0.4};
  const Eigen::Isometry3d turn = rotation(0.25, {0, 0, 1});
  for (double gap : kGaps) {
    SCOPED_TRACE(gap);
    const Placed standing = at(cylinder, {0.1, -0.2, 0.4 + gap}, turn);
    for (bool reversed : {false, true}) {
      const auto contacts = on_slab(standing, 0.1, reversed);
      ASSERT_EQ(contacts.size(), 4u);
      std::vector<int> features;
      std::vector<Eigen::Vector3d> points;
      for (const OnSlab& c : contacts) {
        EXPECT_NEAR(c.gap, gap, kExact);
        ASSERT_LT(c.feature, kRimPoints);  // the incident (cylinder's) bottom rim point j: feature j
        const Eigen::Vector3d rim = cylinder_rim_point(cylinder, 0, c.feature);
        expect_near(c.upper_point, local(standing.pose * rim), kExact);
        expect_near(c.upper_arm, standing.pose.linear() * rim, kExact);
        EXPECT_NEAR(c.upper_point.z(), gap, kExact);
        features.push_back(c.feature);
        points.push_back(c.upper_point);
      }
      std::sort(features.begin(), features.end());
      EXPECT_EQ(features, (std::vector<int>{0, 2, 4, 6}));
      EXPECT_NEAR(polygon_area(points), 2.0 * 0.3 * 0.3, 1e-12);
    }
  }
  EXPECT_TRUE(on_slab(at(cylinder, {0.1, -0.2, 0.4 + 0.11}, turn), 0.1, false).empty());
}

TEST(ConvexManifold, CylinderRestingKeepsItsFourRimPointsUnderRoundOffTilts) {
  // A body at rest tilts by round-off from step to step: the points kept (and so the warm start's
  // keys) must not hop between the two alternate squares of the octagon. Tilts of 1e-13 rad change the
  // rim points' heights by 3e-14 m, within the reduction's tie slack (1e-9 × 0.5 m).
  const Cylinder cylinder{0.3, 0.4};
  for (const Eigen::Vector3d& axis : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(1, -1, 0)})
    for (double tilt : {1e-13, -1e-13}) {
      const Placed standing = at(cylinder, {0.1, -0.2, 0.4 + 1e-5}, rotation(tilt, axis));
      std::vector<int> features;
      for (const OnSlab& c : on_slab(standing, 0.1, false)) features.push_back(c.feature);
      std::sort(features.begin(), features.end());
      EXPECT_EQ(features, (std::vector<int>{0, 2, 4, 6}));
    }
}

TEST(ConvexManifold, CylinderLyingOnABoxRestsOnItsLowestGenerator) {
  // Along the local x, axis at height r + gap: the generator's ends (features 16, 17, not material).
  const Cylinder cylinder{0.3, 0.4};
  for (double gap : kGaps) {
    SCOPED_TRACE(gap);
    const Placed lying = at(cylinder, {0.1, -0.2, 0.3 + gap}, kAlongX);
    const auto contacts = on_slab(lying, 0.1, false);
    ASSERT_EQ(contacts.size(), 2u);
    for (const OnSlab& c : contacts) {
      EXPECT_NEAR(c.gap, gap, kExact);
      ASSERT_TRUE(c.feature == 2 * kRimPoints || c.feature == 2 * kRimPoints + 1);
      EXPECT_TRUE(std::isnan(c.upper_arm.x()));
      // kAlongX turns the shape's z onto the local +x: rim 0 (z = −0.4) at x = 0.1 − 0.4.
      const Eigen::Vector3d end = local(lying.pose * Eigen::Vector3d(0, 0, c.feature == 2 * kRimPoints ? -0.4 : 0.4));
      expect_near(c.upper_point, {end.x(), -0.2, gap}, kExact);
    }
  }
}

TEST(ConvexManifold, CapsuleLyingOnABoxRestsOnItsCoreEnds) {
  // Radius 0.2, core half length 0.5 along a horizontal direction at 0.3 rad from the local x, core at
  // height 0.2 + gap: two points, under the core's ends, gap = the core's height − radius.
  const Capsule capsule{0.2, 0.5};
  const Eigen::Isometry3d turn = rotation(0.3, {0, 0, 1}) * kAlongX;
  for (double gap : kGaps) {
    SCOPED_TRACE(gap);
    const Placed lying = at(capsule, {0.1, 0.2, 0.2 + gap}, turn);
    for (bool reversed : {false, true}) {
      const auto contacts = on_slab(lying, 0.1, reversed);
      ASSERT_EQ(contacts.size(), 2u);
      for (const OnSlab& c : contacts) {
        EXPECT_NEAR(c.gap, gap, kExact);
        ASSERT_TRUE(c.feature == 0 || c.feature == 1);  // the core's end at z = −h, +h
        const Eigen::Vector3d end = local(lying.pose * Eigen::Vector3d(0, 0, c.feature == 0 ? -0.5 : 0.5));
        expect_near(c.upper_point, {end.x(), end.y(), gap}, kExact);
      }
    }
  }
}

TEST(ConvexManifold, CapsuleHangingOverTheEdgeRestsOnTheFacesEdge) {
  // The capsule's core runs from local x = 0.6 to 1.6, the face ends at x = 1: the points are the core's
  // inner end and its crossing of the face's side x = 1 (a crossing: feature 2 V + V i + j, V = 8).
  const Placed lying = at(Capsule{0.2, 0.5}, {1.1, 0.0, 0.2 + 0.001}, kAlongX);
  const auto contacts = on_slab(lying, 0.01, false);
  ASSERT_EQ(contacts.size(), 2u);
  std::vector<double> xs;
  for (const OnSlab& c : contacts) {
    EXPECT_NEAR(c.gap, 0.001, kExact);
    EXPECT_NEAR(c.upper_point.y(), 0.0, kExact);
    xs.push_back(c.upper_point.x());
  }
  std::sort(xs.begin(), xs.end());
  EXPECT_NEAR(xs[0], 0.6, kExact);
  EXPECT_NEAR(xs[1], 1.0, kExact);
}

std::vector<Eigen::Vector3d> prism_points(int sides, double radius, double half_height) {
  std::vector<Eigen::Vector3d> points;
  for (double z : {-half_height, half_height})
    for (int k = 0; k < sides; ++k)
      points.emplace_back(radius * std::cos(2 * kPi * k / sides), radius * std::sin(2 * kPi * k / sides), z);
  return points;
}

TEST(ConvexManifold, TriangularPrismOnABoxRestsOnItsBottomFacesVertices) {
  // A hull's bottom face (a triangle: vertices 0, 1, 2 of those given) over the box face at height gap:
  // its three vertices, material points with their arms.
  const Convex prism = make_convex(prism_points(3, 0.2, 0.05));
  for (double gap : kGaps) {
    SCOPED_TRACE(gap);
    const Placed resting = at(prism, {0.1, -0.1, 0.05 + gap}, rotation(0.4, {0, 0, 1}));
    for (bool reversed : {false, true}) {
      const auto contacts = on_slab(resting, 0.1, reversed);
      ASSERT_EQ(contacts.size(), 3u);
      std::vector<int> features;
      for (const OnSlab& c : contacts) {
        EXPECT_NEAR(c.gap, gap, kExact);
        ASSERT_LT(c.feature, 6);
        expect_near(c.upper_point, local(resting.pose * prism.vertices[c.feature]), kExact);
        expect_near(c.upper_arm, resting.pose.linear() * prism.vertices[c.feature], kExact);
        features.push_back(c.feature);
      }
      std::sort(features.begin(), features.end());
      EXPECT_EQ(features, (std::vector<int>{0, 1, 2}));
    }
  }
}

TEST(ConvexManifold, HexagonalPrismOnABoxKeepsFourVerticesOfTheLargestArea) {
  // Six bottom vertices over the face; the four kept span the largest quadrilateral of a regular
  // hexagon's vertices, a rectangle R × √3 R.
  const double R = 0.15;
  const Convex prism = make_convex(prism_points(6, R, 0.05));
  const Placed resting = at(prism, {0.2, 0.1, 0.05 + 1e-4});
  const auto contacts = on_slab(resting, 0.01, false);
  ASSERT_EQ(contacts.size(), 4u);
  std::vector<Eigen::Vector3d> points;
  for (const OnSlab& c : contacts) {
    EXPECT_NEAR(c.gap, 1e-4, kExact);
    ASSERT_LT(c.feature, 6);  // bottom vertices
    points.push_back(c.upper_point);
  }
  EXPECT_NEAR(polygon_area(points), std::sqrt(3.0) * R * R, 1e-12);
}

TEST(ConvexManifold, ParallelCapsulesTouchAtTheEndsOfTheirOverlap) {
  // a: radius 0.2, core x ∈ [−0.5, 0.5]; b: radius 0.15, core half length 0.35, beside it along y at
  // distance 0.35 + gap. Centred at x = 0.15 (core [−0.2, 0.5]): b's two ends over a's core (features
  // 0, 1). Centred at x = 0.4 (core [0.05, 0.75]): b's end at 0.05 and a's end at 0.5 (a reference
  // point: feature V + 1 = 3). Gap = distance − r1 − r2.
  const Placed a = at(Capsule{0.2, 0.5}, {0, 0, 0}, kAlongX);
  const Eigen::Vector3d ey = kScene.linear() * Eigen::Vector3d::UnitY();
  for (double gap : kGaps) {
    SCOPED_TRACE(gap);
    const double tolerance = gap < 0.0 ? kCurved : kFcl;
    for (double centre : {0.15, 0.4}) {
      const Placed b = at(Capsule{0.15, 0.35}, {centre, 0.35 + gap, 0}, kAlongX);
      for (bool reversed : {false, true}) {
        const auto contacts = detect(a, b, 0.1, reversed);
        ASSERT_EQ(contacts.size(), 2u);
        std::vector<double> xs;
        for (const ContactPoint& c : contacts) {
          EXPECT_NEAR(c.gap, gap, tolerance);
          expect_near(reversed ? Eigen::Vector3d(-c.normal) : c.normal, ey, tolerance);
          const Eigen::Vector3d on_a = local(reversed ? c.point_b : c.point_a);
          EXPECT_NEAR(on_a.y(), 0.2, tolerance);  // a's surface towards b
          xs.push_back(on_a.x());
        }
        std::sort(xs.begin(), xs.end());
        EXPECT_NEAR(xs[0], centre - 0.35, tolerance);
        EXPECT_NEAR(xs[1], 0.5, tolerance);
      }
    }
  }
}

// ---- a box's or hull's edge along a capsule's or cylinder's side -----------------------------------
//
// The lower shape lies along the local x, radius 0.2, core (or axis) x ∈ [−0.5, 0.5] at the origin.
// The upper box, half extents (hx, 0.1, 0.1), is turned 45° about its x so that an edge along x is
// its lowest line, 0.1 √2 below its centre; its centre at (cx, 0, 0.2 + 0.1 √2 + gap). No face is
// along the normal (+z local): the edge and the core (or the side generator) are two parallel segments
// and touch along their overlap, each point at (x, 0, 0.2) on the lower shape and (x, 0, 0.2 + gap) on
// the box. The longer segment is the reference:
//   hx = 0.3, cx = 0.1: the edge x ∈ [−0.2, 0.4], shorter than the core, lies over it: its two ends;
//   hx = 0.6, cx = 0.4: the edge x ∈ [−0.2, 1.0], the longer: its end at −0.2 and the core's end at 0.5.
// Features (convex_manifold.h): the box is the first shape (V = max(8, lower's bound)); a point of the
// edge is the box's vertex v, a point of the core its end k (a cylinder's generator end 16 + k).

struct EdgeCase {
  double half_x, centre_x, low_x, high_x;
};
constexpr EdgeCase kEdgeCases[] = {{0.3, 0.1, -0.2, 0.4}, {0.6, 0.4, -0.2, 0.5}};
const Eigen::Isometry3d kOnEdge = rotation(kPi / 4, {1, 0, 0});

Placed box_on_edge(const EdgeCase& e, double gap, const Eigen::Isometry3d& turn = Eigen::Isometry3d::Identity()) {
  return at(Box{{e.half_x, 0.1, 0.1}}, {e.centre_x, 0.0, 0.2 + 0.1 * std::sqrt(2.0) + gap}, turn * kOnEdge);
}

// The normal across two parallel segments is their lines' common perpendicular and the gaps are
// heights along it (convex_manifold.h): closed forms, kExact (FCL's GJK normal would be 1e-6 to 1e-5
// rad off here, gjk_pairs.h), overlapping or not.
// Checks the two points of `upper` along `lower`'s side; returns their features, sorted.
std::vector<int> expect_line_contact(const Placed& lower, const Placed& upper, const EdgeCase& e, double gap,
                                     bool reversed) {
  const double tolerance = kExact;
  const auto contacts = detect(lower, upper, 0.1, reversed);
  EXPECT_EQ(contacts.size(), 2u);
  std::vector<double> xs;
  std::vector<int> features;
  for (const ContactPoint& c : contacts) {
    EXPECT_NEAR(c.gap, gap, tolerance);
    expect_near(reversed ? Eigen::Vector3d(-c.normal) : c.normal, kUp, tolerance);
    const Eigen::Vector3d on_lower = local(reversed ? c.point_b : c.point_a);
    const Eigen::Vector3d on_upper = local(reversed ? c.point_a : c.point_b);
    EXPECT_NEAR(on_lower.y(), 0.0, tolerance);
    EXPECT_NEAR(on_lower.z(), 0.2, tolerance);
    EXPECT_NEAR(on_upper.x(), on_lower.x(), tolerance);
    EXPECT_NEAR(on_upper.y(), 0.0, tolerance);
    EXPECT_NEAR(on_upper.z(), 0.2 + gap, tolerance);
    xs.push_back(on_lower.x());
    features.push_back(c.key.feature);
  }
  std::sort(xs.begin(), xs.end());
  std::sort(features.begin(), features.end());
  if (xs.size() == 2) {
    EXPECT_NEAR(xs[0], e.low_x, tolerance);
    EXPECT_NEAR(xs[1], e.high_x, tolerance);
  }
  return features;
}

// The box's vertices on its lowest edge (turned 45° about x, the edge at local y = 0, z lowest):
// y and z both −0.1 in the box frame, so ids 0 (x = −hx) and 1 (x = +hx) of box_vertex's numbering.
Eigen::Vector3d lowest_edge_end(const Placed& box, int v) {
  return local(box.pose * box_vertex(std::get<Box>(box.shape), v, false));
}

TEST(ConvexManifold, BoxEdgeAlongACapsulesSideTouchesAtTheEndsOfTheirOverlap) {
  const Placed capsule = at(Capsule{0.2, 0.5}, {0, 0, 0}, kAlongX);
  for (double gap : kGaps) {
    SCOPED_TRACE(gap);
    for (const EdgeCase& e : kEdgeCases) {
      SCOPED_TRACE(e.half_x);
      const Placed box = box_on_edge(e, gap);
      expect_near(lowest_edge_end(box, 0), {e.centre_x - e.half_x, 0.0, 0.2 + gap}, kExact);
      expect_near(lowest_edge_end(box, 1), {e.centre_x + e.half_x, 0.0, 0.2 + gap}, kExact);
      for (bool reversed : {false, true}) {
        const std::vector<int> features = expect_line_contact(capsule, box, e, gap, reversed);
        // V = 8, P = 128. The core (length 1) the reference: the edge's ends 0, 1 as incident points,
        // offset by P. The edge (length 1.2) the reference: its end 0 (8 + 0) and the core's end 1.
        if (e.half_x < 0.5) EXPECT_EQ(features, (std::vector<int>{128, 129}));
        else EXPECT_EQ(features, (std::vector<int>{1, 8}));
      }
    }
  }
}

TEST(ConvexManifold, BoxEdgeAlongACylindersSideTouchesAtTheEndsOfTheirOverlap) {
  // The same with the cylinder's highest side generator (its end 0.5 the cylinder's rim).
  const Placed cylinder = at(Cylinder{0.2, 0.5}, {0, 0, 0}, kAlongX);
  for (double gap : kGaps) {
    SCOPED_TRACE(gap);
    for (const EdgeCase& e : kEdgeCases) {
      SCOPED_TRACE(e.half_x);
      for (bool reversed : {false, true}) {
        const std::vector<int> features = expect_line_contact(cylinder, box_on_edge(e, gap), e, gap, reversed);
        // V = 18, P = 512; the generator's end k has id 16 + k.
        if (e.half_x < 0.5) EXPECT_EQ(features, (std::vector<int>{512, 513}));
        else EXPECT_EQ(features, (std::vector<int>{17, 18}));
      }
    }
  }
}

TEST(ConvexManifold, CubeHullEdgeAlongACapsulesSideIsTheBoxesContact) {
  // A hull of a box's corners (given in box_vertex's order, so its vertex ids are the box's) on its
  // edge: the same points as the box. The capsule is now the first shape (capsule < convex in the
  // Shape variant): the core the reference, the hull's vertices 0, 1 as incident points; the edge the
  // reference, P + V + 0 = 136 for its end and the core's end 1 as an incident point, P + 1 = 129.
  const Placed capsule = at(Capsule{0.2, 0.5}, {0, 0, 0}, kAlongX);
  for (const EdgeCase& e : kEdgeCases) {
    std::vector<Eigen::Vector3d> corners;
    for (int i = 0; i < 8; ++i) corners.push_back(box_vertex(Box{{e.half_x, 0.1, 0.1}}, i, false));
    Placed hull = box_on_edge(e, 1e-3);
    hull.shape = make_convex(corners);
    for (bool reversed : {false, true}) {
      const std::vector<int> features = expect_line_contact(capsule, hull, e, 1e-3, reversed);
      if (e.half_x < 0.5) EXPECT_EQ(features, (std::vector<int>{0, 1}));
      else EXPECT_EQ(features, (std::vector<int>{129, 136}));
    }
  }
}

TEST(ConvexManifold, BoxEdgeKeepsItsFeaturesUnderSmallMotions) {
  // The warm start's keys: tilts of 1e-7 rad about each axis and shifts of 1e-4 m along the core keep
  // the same two features (the same edge, the same reference).
  const Placed capsule = at(Capsule{0.2, 0.5}, {0, 0, 0}, kAlongX);
  for (const EdgeCase& e : kEdgeCases) {
    const std::vector<int> resting = expect_line_contact(capsule, box_on_edge(e, 1e-4), e, 1e-4, false);
    for (const Eigen::Vector3d& axis : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 1)})
      for (double tilt : {1e-7, -1e-7}) {
        std::vector<int> features;
        for (const ContactPoint& c : detect(capsule, box_on_edge(e, 1e-4, rotation(tilt, axis)), 0.1))
          features.push_back(c.key.feature);
        std::sort(features.begin(), features.end());
        EXPECT_EQ(features, resting) << axis.transpose() << " " << tilt;
      }
    for (double shift : {1e-4, -1e-4}) {
      std::vector<int> features;
      for (const ContactPoint& c : detect(capsule, box_on_edge(e, 1e-4, translation(shift, 0, 0)), 0.1))
        features.push_back(c.key.feature);
      std::sort(features.begin(), features.end());
      EXPECT_EQ(features, resting) << shift;
    }
  }
}

TEST(ConvexManifold, BoxEdgeAcrossACapsuleOrACylinderKeepsGjksSinglePoint) {
  // The edge turned 0.5 rad about the vertical from the core: crossed segments touch at one point,
  // over the core, at the gap (the common normal of the two lines is the vertical).
  for (const Shape& lower : {Shape(Capsule{0.2, 0.5}), Shape(Cylinder{0.2, 0.5})})
    for (double gap : {0.05, 1e-3}) {
      const Placed crossed = box_on_edge(kEdgeCases[0], gap, rotation(0.5, {0, 0, 1}));
      for (bool reversed : {false, true}) {
        const auto contacts = detect(at(lower, {0, 0, 0}, kAlongX), crossed, 0.1, reversed);
        ASSERT_EQ(contacts.size(), 1u);
        EXPECT_EQ(contacts[0].key.feature, 0);
        EXPECT_NEAR(contacts[0].gap, gap, kFcl);
      }
    }
}

TEST(ConvexManifold, ParallelBoxEdgesTouchAtTheEndsOfTheirOverlap) {
  // Two boxes on their edges, one above the other: the lower (half extents 0.5, 0.1, 0.1, turned so
  // that an edge along x is its highest line, at local z = 0.1 √2 + 0.2 − 0.2 = its centre + 0.1 √2)
  // and the upper of kEdgeCases: separated by gap (box–box through GJK when apart), the ends of the
  // edges' overlap, at the gap (kExact: the normal is the edges' common perpendicular).
  const Placed lower = at(Box{{0.5, 0.1, 0.1}}, {0, 0, 0.2 - 0.1 * std::sqrt(2.0)}, kOnEdge);
  for (double gap : {0.05, 1e-3}) {
    for (const EdgeCase& e : kEdgeCases) {
      SCOPED_TRACE(e.half_x);
      for (bool reversed : {false, true}) {
        const auto contacts = detect(lower, box_on_edge(e, gap), 0.1, reversed);
        ASSERT_EQ(contacts.size(), 2u);
        std::vector<double> xs;
        for (const ContactPoint& c : contacts) {
          EXPECT_NEAR(c.gap, gap, kExact);
          const Eigen::Vector3d on_lower = local(reversed ? c.point_b : c.point_a);
          expect_near(on_lower, {on_lower.x(), 0.0, 0.2}, kExact);
          xs.push_back(on_lower.x());
        }
        std::sort(xs.begin(), xs.end());
        EXPECT_NEAR(xs[0], e.low_x, kExact);
        EXPECT_NEAR(xs[1], e.high_x, kExact);
      }
    }
  }
}

TEST(ConvexManifold, CylinderStandingOnACylindersCapRestsOnFourOfItsRimPoints) {
  // Upper radius 0.2 (half length 0.3), its axis 0.07 off the lower one's (radius 0.3): its bottom rim
  // lies within the lower cap's octagon (inradius 0.3 cos 22.5° = 0.277 > 0.2 + 0.071). The lower cap
  // is the reference (the larger); the upper rim points are the incident points.
  for (double gap : kGaps) {
    SCOPED_TRACE(gap);
    const Placed lower = at(Cylinder{0.3, 0.4}, {0, 0, -0.4});
    const Placed upper = at(Cylinder{0.2, 0.3}, {0.05, 0.05, 0.3 + gap}, rotation(0.4, {0, 0, 1}));
    const auto contacts = detect(lower, upper, 0.1);
    ASSERT_EQ(contacts.size(), 4u);
    for (const ContactPoint& c : contacts) {
      EXPECT_NEAR(c.gap, gap, kExact);
      expect_near(c.normal, kUp, kExact);
      ASSERT_LT(c.key.feature, kRimPoints);
      expect_near(c.point_b, upper.pose * cylinder_rim_point(Cylinder{0.2, 0.3}, 0, c.key.feature), kExact);
    }
  }
}

TEST(ConvexManifold, CylinderOnAHullAndCubeHullsStacked) {
  // A cylinder standing on a hexagonal prism's top face, and a cube given as a hull on a larger one:
  // 4 points at the gap, the normal the face's.
  const Convex prism = make_convex(prism_points(6, 0.5, 0.1));
  const Placed base = at(prism, {0, 0, -0.1});
  const Placed standing = at(Cylinder{0.2, 0.3}, {0.05, 0, 0.3 + 0.002});
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i) corners.push_back(box_vertex(Box{{0.1, 0.1, 0.1}}, i, false));
  const Placed cube = at(make_convex(corners), {-0.05, 0.1, 0.1 + 0.002}, rotation(0.3, {0, 0, 1}));
  for (const Placed& upper : {standing, cube}) {
    for (bool reversed : {false, true}) {
      const auto contacts = detect(base, upper, 0.01, reversed);
      ASSERT_EQ(contacts.size(), 4u);
      for (const ContactPoint& c : contacts) {
        EXPECT_NEAR(c.gap, 0.002, kExact);
        expect_near(reversed ? Eigen::Vector3d(-c.normal) : c.normal, kUp, kExact);
        EXPECT_NEAR(local(reversed ? c.point_a : c.point_b).z(), 0.002, kExact);
      }
    }
  }
}

TEST(ConvexManifold, TiltedShapesKeepGjksSinglePoint) {
  // A cylinder tilted 0.3 rad on its rim, a capsule tilted 0.3 rad onto one cap, two capsules crossed
  // at 0.5 rad, a tetrahedron on a vertex: one point (feature 0) at GJK's closest points.
  const double tilt = 0.3;
  const Cylinder cylinder{0.3, 0.4};
  // The lowest rim point of a cylinder turned by `tilt` about y is r sin(tilt) + h cos(tilt) below its centre.
  const double reach = 0.3 * std::sin(tilt) + 0.4 * std::cos(tilt);
  const Placed tilted_cylinder = at(cylinder, {0, 0, reach + 0.001}, rotation(tilt, {0, 1, 0}));
  const Placed tilted_capsule = at(Capsule{0.2, 0.5}, {0, 0, 0.2 + 0.5 * std::sin(tilt) + 0.001},
                                   rotation(kPi / 2 - tilt, {0, 1, 0}));
  std::vector<Eigen::Vector3d> tetrahedron = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  for (auto& p : tetrahedron) p *= 0.1;
  const Eigen::Vector3d down = Eigen::Vector3d(1, 1, 1).normalized();  // vertex 0 turned to −z
  const Placed tetra = at(make_convex(tetrahedron), {0, 0, 0.1 * std::sqrt(3.0) + 0.001},
                          rotation(std::acos(-down.z()), down.cross(-Eigen::Vector3d::UnitZ())));
  for (const Placed& upper : {tilted_cylinder, tilted_capsule, tetra}) {
    for (bool reversed : {false, true}) {
      const auto contacts = detect(kSlab, upper, 0.01, reversed);
      ASSERT_EQ(contacts.size(), 1u);
      EXPECT_EQ(contacts[0].key.feature, 0);
      EXPECT_NEAR(contacts[0].gap, 0.001, kFcl);
    }
  }
  const Placed a = at(Capsule{0.2, 0.5}, {0, 0, 0}, kAlongX);
  const Placed crossed = at(Capsule{0.15, 0.35}, {0.1, 0, 0.35 + 0.001}, rotation(0.5, {0, 0, 1}) * kAlongX);
  const auto contacts = detect(a, crossed, 0.01);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].key.feature, 0);
  EXPECT_NEAR(contacts[0].gap, 0.001, kFcl);
}

}  // namespace
}  // namespace csim
