// The smoothed boundary (boundary_curve.h) and its contacts (deformable_surface.h): interpolation of the
// nodes, reproduction of straight lines and of quadratic edges, C1 continuity and the O(h⁴) distance
// to a circle, and each contact row against finite differences of the gap.
#include "contact/boundary_curve.h"
#include "contact/collision_world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace csim {
namespace {

// A closed chain of n nodes on a circle of radius R, counter-clockwise (outward order).
struct Chain {
  std::vector<Eigen::Vector3d> nodes;
  std::vector<std::array<int, 2>> segments;
};

Chain circle(int n, double radius) {
  Chain c;
  for (int i = 0; i < n; ++i) {
    const double angle = 2.0 * std::numbers::pi * i / n;
    c.nodes.emplace_back(radius * std::cos(angle), radius * std::sin(angle), 0.0);
    c.segments.push_back({i, (i + 1) % n});
  }
  return c;
}

// The boundary of a w × h rectangle with `per_side` segments on each side, counter-clockwise.
Chain rectangle(double w, double h, int per_side) {
  Chain c;
  const Eigen::Vector3d corners[4] = {{0, 0, 0}, {w, 0, 0}, {w, h, 0}, {0, h, 0}};
  for (int side = 0; side < 4; ++side)
    for (int k = 0; k < per_side; ++k)
      c.nodes.push_back(corners[side] + (corners[(side + 1) % 4] - corners[side]) * k / per_side);
  const int n = static_cast<int>(c.nodes.size());
  for (int i = 0; i < n; ++i) c.segments.push_back({i, (i + 1) % n});
  return c;
}

double weight_sum(const SurfacePoint& p) {
  double sum = 0.0;
  for (int k = 0; k < p.count; ++k) sum += p.weights[k];
  return sum;
}

TEST(BoundaryCurve, CatmullRomPassesThroughTheNodesAndIsC1) {
  const Chain c = circle(12, 2.0);
  const auto curve = catmull_rom_segments(c.segments, c.nodes);
  ASSERT_EQ(curve.size(), 12u);
  for (std::size_t i = 0; i < curve.size(); ++i) {
    EXPECT_EQ(curve[i].count, 4);  // 30° turns: no corner, four nodes each
    EXPECT_NEAR(weight_sum(curve_point(curve[i], 0.37)), 1.0, 1e-15);
    EXPECT_NEAR(weight_sum(curve_derivative(curve[i], 0.37)), 0.0, 1e-15);
    EXPECT_LT((surface_position(curve_point(curve[i], 0.0), c.nodes) - c.nodes[c.segments[i][0]]).norm(), 1e-15);
    EXPECT_LT((surface_position(curve_point(curve[i], 1.0), c.nodes) - c.nodes[c.segments[i][1]]).norm(), 1e-15);
    const auto& next = curve[(i + 1) % curve.size()];
    EXPECT_LT((surface_position(curve_derivative(curve[i], 1.0), c.nodes) -
               surface_position(curve_derivative(next, 0.0), c.nodes)).norm(), 1e-14);
  }
}

TEST(BoundaryCurve, CatmullRomReproducesStraightLines) {
  // Equally spaced collinear nodes: the curve is the line with the uniform parameter.
  Chain line;
  for (int i = 0; i < 5; ++i) line.nodes.emplace_back(0.3 + 0.5 * i, -0.2 + 0.25 * i, 0.0);
  for (int i = 0; i < 4; ++i) line.segments.push_back({i, i + 1});
  for (std::size_t i = 0; i < 4; ++i) {
    const auto segment = catmull_rom_segments(line.segments, line.nodes)[i];
    for (double s : {0.0, 0.1127, 0.5, 0.8873, 1.0}) {
      const Eigen::Vector3d expected = line.nodes[i] + s * (line.nodes[i + 1] - line.nodes[i]);
      EXPECT_LT((surface_position(curve_point(segment, s), line.nodes) - expected).norm(), 1e-14);
    }
  }
  // Unequal spacing: the points stay on the line (weights sum to 1).
  line.nodes[1] = line.nodes[0] + 0.2 * (line.nodes[4] - line.nodes[0]);
  line.nodes[2] = line.nodes[0] + 0.3 * (line.nodes[4] - line.nodes[0]);
  const Eigen::Vector3d direction = (line.nodes[4] - line.nodes[0]).normalized();
  for (const auto& segment : catmull_rom_segments(line.segments, line.nodes))
    for (double s : {0.1127, 0.5, 0.8873}) {
      const Eigen::Vector3d x = surface_position(curve_point(segment, s), line.nodes) - line.nodes[0];
      EXPECT_LT(x.cross(direction).norm(), 1e-14);
    }
}

TEST(BoundaryCurve, CornersAreKeptAndSidesStayStraight) {
  // A rectangle's sides, each a straight run broken at the 90° corners: every point on its side.
  const Chain c = rectangle(2.0, 1.0, 3);
  const auto curve = catmull_rom_segments(c.segments, c.nodes);
  for (std::size_t i = 0; i < 3; ++i)  // the bottom side, y = 0
    for (double s : kCurveGaussAbscissae)
      EXPECT_NEAR(surface_position(curve_point(curve[i], s), c.nodes).y(), 0.0, 1e-15);
  for (std::size_t i = 3; i < 6; ++i)  // the right side, x = 2
    for (double s : kCurveGaussAbscissae)
      EXPECT_NEAR(surface_position(curve_point(curve[i], s), c.nodes).x(), 2.0, 1e-15);
}

// Largest |‖x(s)‖ − R| over the curve of an n-gon inscribed in the circle of radius R.
double distance_to_circle(int n, double radius) {
  const Chain c = circle(n, radius);
  const auto curve = catmull_rom_segments(c.segments, c.nodes);
  double largest = 0.0;
  for (int k = 0; k <= 100; ++k)
    largest = std::max(largest, std::abs(surface_position(curve_point(curve[0], k / 100.0), c.nodes).norm() - radius));
  return largest;
}

TEST(BoundaryCurve, CatmullRomFollowsACircleToFourthOrder) {
  // The chords of the 34-gon leave a sagitta R (1 − cos(π/34)); the cubic follows the circle to O(h⁴):
  // halving h divides its distance by 16.
  const double radius = 2.0;
  const double sagitta = radius * (1.0 - std::cos(std::numbers::pi / 34));
  EXPECT_LT(distance_to_circle(34, radius), 0.01 * sagitta);
  EXPECT_NEAR(distance_to_circle(34, radius) / distance_to_circle(68, radius), 16.0, 0.5);
  EXPECT_NEAR(distance_to_circle(68, radius) / distance_to_circle(136, radius), 16.0, 0.5);
}

TEST(BoundaryCurve, QuadraticEdgeIsTheElementEdge) {
  // Nodes on the parabola y = x² (corner a at x = −1, corner b at x = 1, mid-side at x = 0): the edge is
  // that parabola, x(s) = 2s − 1.
  const std::vector<Eigen::Vector3d> nodes = {{-1, 1, 0}, {1, 1, 0}, {0, 0, 0}};
  const auto curve = quadratic_segments({{0, 1, 2}});
  ASSERT_EQ(curve.size(), 1u);
  for (double s : {0.0, 0.25, 0.5, 0.8873, 1.0}) {
    const Eigen::Vector3d x = surface_position(curve_point(curve[0], s), nodes);
    EXPECT_NEAR(x.x(), 2.0 * s - 1.0, 1e-15);
    EXPECT_NEAR(x.y(), x.x() * x.x(), 1e-15);
    EXPECT_NEAR(surface_position(curve_derivative(curve[0], s), nodes).x(), 2.0, 1e-14);
  }
}

// The smoothed contacts of a circle's boundary with `shape`, with the circle's object first (a) or second.
std::vector<ContactPoint> smoothed_contacts(const std::vector<Eigen::Vector3d>& nodes, const Chain& chain,
                                            const Shape& shape, const Eigen::Isometry3d& pose, bool surface_is_a) {
  DeformableSurfaceGeometry geometry;
  geometry.segments = chain.segments;
  geometry.curve = catmull_rom_segments(chain.segments, chain.nodes);
  std::vector<ContactPoint> out;
  curve_shape_contacts(nodes, geometry, shape, pose, 0.5, surface_is_a, true, static_cast<int>(nodes.size()), out);
  return out;
}

// d gap / d x_k against the row's entry: the normal row is the gap's rate, u_n = n·(v_B − v_A), so the
// surface's entries are ∓ n · w_k(s_g) as it is A or B.
void expect_rows_match_finite_differences(const Shape& shape, const Eigen::Isometry3d& pose, bool surface_is_a) {
  const Chain chain = circle(16, 1.0);
  std::vector<Eigen::Vector3d> nodes = chain.nodes;
  for (std::size_t i = 0; i < nodes.size(); ++i) nodes[i] *= 1.0 + 0.02 * std::sin(3.0 * i);  // deformed
  const auto contacts = smoothed_contacts(nodes, chain, shape, pose, surface_is_a);
  ASSERT_GE(contacts.size(), 3u);
  const double step = 1e-6;
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const ContactPoint& c = contacts[i];
    EXPECT_GE(c.key.feature, static_cast<int>(nodes.size()));
    if (i > 0) {
      EXPECT_GT(c.key.feature, contacts[i - 1].key.feature);
    }
    for (int k = 0; k < c.surface.count; ++k)
      for (int component = 0; component < 2; ++component) {
        const double row = (surface_is_a ? -1.0 : 1.0) * c.normal(component) * c.surface.weights[k];
        std::vector<Eigen::Vector3d> moved = nodes;
        double gaps[2];
        for (int side = 0; side < 2; ++side) {
          moved[c.surface.nodes[k]](component) = nodes[c.surface.nodes[k]](component) + (side ? step : -step);
          const auto again = smoothed_contacts(moved, chain, shape, pose, surface_is_a);
          const auto same = std::find_if(again.begin(), again.end(),
                                         [&](const ContactPoint& x) { return x.key.feature == c.key.feature; });
          ASSERT_NE(same, again.end());
          gaps[side] = same->gap;
        }
        EXPECT_NEAR((gaps[1] - gaps[0]) / (2.0 * step), row, 1e-8);
      }
  }
}

TEST(BoundaryCurve, RowsMatchFiniteDifferencesOnAHalfspace) {
  const Eigen::Isometry3d pose(Eigen::Translation3d(0.0, -0.97, 0.0));
  expect_rows_match_finite_differences(Halfspace{Eigen::Vector3d(0.1, 1.0, 0.0).normalized(), 0.0}, pose, true);
  expect_rows_match_finite_differences(Halfspace{Eigen::Vector3d(0.1, 1.0, 0.0).normalized(), 0.0}, pose, false);
}

TEST(BoundaryCurve, RowsMatchFiniteDifferencesOnASphere) {
  // A curved shape: the normal turns with the point, the gap's first derivative is still n·δx.
  const Eigen::Isometry3d pose(Eigen::Translation3d(0.3, -1.6, 0.0));
  expect_rows_match_finite_differences(Sphere{0.65}, pose, true);
  expect_rows_match_finite_differences(Sphere{0.65}, pose, false);
}

TEST(BoundaryCurve, CollisionWorldGivesSmoothedFeaturesOnly) {
  const Chain chain = circle(16, 1.0);
  DeformableSurfaceGeometry geometry;
  geometry.segments = chain.segments;
  geometry.contact_nodes.resize(16);
  for (int i = 0; i < 16; ++i) geometry.contact_nodes[i] = i;
  geometry.curve = catmull_rom_segments(chain.segments, chain.nodes);
  CollisionWorld world(true);
  world.add_object(0, Halfspace{Eigen::Vector3d::UnitY(), -0.99}, true);
  const int surface = world.add_deformable_surface(1, chain.nodes, geometry);
  world.set_surface_features(surface, 0, SurfaceFeatures::smoothed);
  world.update(0.0);
  std::vector<ContactPoint> contacts;
  world.find_contacts(contacts);
  // The bottom node (at −1) penetrates by 0.01; the Gauss points of its two segments nearest it.
  ASSERT_FALSE(contacts.empty());
  for (const ContactPoint& c : contacts) {
    EXPECT_GE(c.key.feature, 16);
    EXPECT_TRUE(c.normal.isApprox(Eigen::Vector3d::UnitY()));
    EXPECT_NEAR(c.gap, (c.point_b - c.point_a).dot(c.normal), 1e-15);
    EXPECT_LT(c.gap, 0.0);
  }
}

}  // namespace
}  // namespace csim
