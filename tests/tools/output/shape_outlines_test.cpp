// The shapes' outlines (tools/output/shape_outlines.h) against closed forms: every vertex on its shape
// (sphere at distance r, box corners at ±h, halfspace patch on n·x = offset), closed surfaces whose
// every edge two polygons share in opposite directions, and orientation from outside checked by the
// signed volume (divergence theorem) or, in the plane, the signed area.
#include "tools/output/shape_outlines.h"

#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <map>
#include <numbers>
#include <utility>

namespace csim {
namespace {

// Σ over polygons, each a fan of triangles (a, b, c), of a · (b × c) / 6: the enclosed volume, positive
// when every polygon runs counter-clockwise seen from outside.
double signed_volume(const ShapeOutline& outline) {
  double volume = 0.0;
  for (const std::vector<int>& polygon : outline.polygons)
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k)
      volume += outline.points[polygon[0]].dot(outline.points[polygon[k]].cross(outline.points[polygon[k + 1]])) / 6.0;
  return volume;
}

// The shoelace area of a plane outline's polygons, positive counter-clockwise seen from +z.
double signed_area(const ShapeOutline& outline) {
  double area = 0.0;
  for (const std::vector<int>& polygon : outline.polygons)
    for (std::size_t k = 0; k < polygon.size(); ++k) {
      const Eigen::Vector3d& a = outline.points[polygon[k]];
      const Eigen::Vector3d& b = outline.points[polygon[(k + 1) % polygon.size()]];
      area += 0.5 * (a.x() * b.y() - a.y() * b.x());
    }
  return area;
}

// Every directed edge once, and its reverse once: a closed surface, consistently oriented.
void expect_closed(const ShapeOutline& outline) {
  std::map<std::pair<int, int>, int> edges;
  for (const std::vector<int>& polygon : outline.polygons)
    for (std::size_t k = 0; k < polygon.size(); ++k) ++edges[{polygon[k], polygon[(k + 1) % polygon.size()]}];
  for (const auto& [edge, count] : edges) {
    EXPECT_EQ(count, 1) << edge.first << "-" << edge.second;
    EXPECT_EQ(edges.count({edge.second, edge.first}), 1u) << edge.first << "-" << edge.second;
  }
}

TEST(ShapeOutlines, SphereIsAClosedPolyhedronInscribedInTheSphere) {
  const double r = 0.3;
  const ShapeOutline outline = sphere_outline(Sphere{r}, {});
  EXPECT_EQ(outline.points.size(), 2u + (kSphereRings - 1u) * kSphereSegments);
  EXPECT_EQ(outline.polygons.size(), static_cast<std::size_t>(kSphereRings * kSphereSegments));
  for (const Eigen::Vector3d& p : outline.points) EXPECT_NEAR(p.norm(), r, 1e-15);
  expect_closed(outline);
  // Inscribed: less than the sphere's volume, more than that of the octahedron on its poles and equator.
  const double volume = signed_volume(outline);
  EXPECT_LT(volume, 4.0 / 3.0 * std::numbers::pi * r * r * r);
  EXPECT_GT(volume, 4.0 / 3.0 * r * r * r);
  EXPECT_TRUE(outline.lines.empty());
}

TEST(ShapeOutlines, DiskIsARegularPolygonOnTheCircle) {
  const double r = 0.3;
  const ShapeOutline outline = sphere_outline(Sphere{r}, {.dimension = 2});
  ASSERT_EQ(outline.polygons.size(), 1u);
  EXPECT_EQ(outline.points.size(), static_cast<std::size_t>(kDiskSides));
  for (const Eigen::Vector3d& p : outline.points) {
    EXPECT_NEAR(p.norm(), r, 1e-15);
    EXPECT_EQ(p.z(), 0.0);
  }
  // A regular N-gon inscribed in a circle of radius r: area N r² sin(2π/N) / 2, counter-clockwise.
  EXPECT_NEAR(signed_area(outline), 0.5 * kDiskSides * r * r * std::sin(2.0 * std::numbers::pi / kDiskSides), 1e-15);
}

TEST(ShapeOutlines, BoxIsItsCornersAndSixOutwardFaces) {
  const Eigen::Vector3d h(0.2, 0.3, 0.5);
  const ShapeOutline outline = box_outline(Box{h}, {});
  ASSERT_EQ(outline.points.size(), 8u);
  EXPECT_EQ(outline.polygons.size(), 6u);
  for (const Eigen::Vector3d& p : outline.points) EXPECT_EQ(p.cwiseAbs(), h);
  for (std::size_t i = 0; i < 8; ++i)
    for (std::size_t j = 0; j < i; ++j) EXPECT_NE(outline.points[i], outline.points[j]);
  expect_closed(outline);
  EXPECT_NEAR(signed_volume(outline), 8.0 * h.prod(), 1e-15);
}

TEST(ShapeOutlines, PlaneBoxIsOneCounterClockwiseRectangle) {
  const Eigen::Vector3d h(0.2, 0.3, 0.5);
  const ShapeOutline outline = box_outline(Box{h}, {.dimension = 2});
  ASSERT_EQ(outline.points.size(), 4u);
  for (const Eigen::Vector3d& p : outline.points) {
    EXPECT_EQ(p.head<2>().cwiseAbs(), h.head<2>());
    EXPECT_EQ(p.z(), 0.0);
  }
  EXPECT_NEAR(signed_area(outline), 4.0 * h.x() * h.y(), 1e-15);
}

TEST(ShapeOutlines, HalfspaceIsASquareOnItsBoundaryFacingOut) {
  const Eigen::Vector3d n = Eigen::Vector3d(1.0, 2.0, 2.0) / 3.0;
  const double offset = 0.5, s = 2.0;
  const ShapeOutline outline = halfspace_outline(Halfspace{n, offset}, {.halfspace_half_side = s});
  ASSERT_EQ(outline.points.size(), 4u);
  ASSERT_EQ(outline.polygons.size(), 1u);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : outline.points) {
    EXPECT_NEAR(n.dot(p), offset, 1e-15);
    centre += p / 4.0;
  }
  EXPECT_NEAR((centre - offset * n).norm(), 0.0, 1e-15);
  const std::vector<int>& q = outline.polygons[0];
  for (std::size_t k = 0; k < 4; ++k)  // a square of side 2s
    EXPECT_NEAR((outline.points[q[k]] - outline.points[q[(k + 1) % 4]]).norm(), 2.0 * s, 1e-14);
  // Counter-clockwise seen from +n (outside the material): (p1 − p0) × (p2 − p0) along +n.
  const Eigen::Vector3d normal =
      (outline.points[q[1]] - outline.points[q[0]]).cross(outline.points[q[2]] - outline.points[q[0]]);
  EXPECT_NEAR(normal.normalized().dot(n), 1.0, 1e-15);
}

TEST(ShapeOutlines, PlaneHalfspaceIsASegmentOfItsBoundaryLine) {
  const Eigen::Vector3d n(0.6, 0.8, 0.0);
  const double offset = -0.25, s = 1.5;
  const ShapeOutline outline = halfspace_outline(Halfspace{n, offset}, {.dimension = 2, .halfspace_half_side = s});
  ASSERT_EQ(outline.points.size(), 2u);
  ASSERT_EQ(outline.lines.size(), 1u);
  EXPECT_TRUE(outline.polygons.empty());
  for (const Eigen::Vector3d& p : outline.points) {
    EXPECT_NEAR(n.dot(p), offset, 1e-15);
    EXPECT_EQ(p.z(), 0.0);
  }
  EXPECT_NEAR((outline.points[0] - outline.points[1]).norm(), 2.0 * s, 1e-15);
  EXPECT_NEAR((0.5 * (outline.points[0] + outline.points[1]) - offset * n).norm(), 0.0, 1e-15);
}

TEST(ShapeOutlines, CapsuleIsAClosedSurfaceOnTheCapsule) {
  const double r = 0.2, l = 0.5;
  const ShapeOutline outline = capsule_outline(Capsule{r, l}, {});
  expect_closed(outline);
  for (const Eigen::Vector3d& p : outline.points) {  // distance r from the axis segment
    const Eigen::Vector3d on_axis(0.0, 0.0, std::clamp(p.z(), -l, l));
    EXPECT_NEAR((p - on_axis).norm(), r, 1e-15);
  }
  // Inscribed: less than the capsule's volume, more than the inscribed sphere polyhedron plus the
  // inscribed prism of the cylinder part.
  const double volume = signed_volume(outline);
  const double pi = std::numbers::pi;
  EXPECT_LT(volume, 4.0 / 3.0 * pi * r * r * r + pi * r * r * 2.0 * l);
  EXPECT_GT(volume, signed_volume(sphere_outline(Sphere{r}, {})) + 2.0 * l * 0.5 * kSphereSegments * r * r *
                                                                       std::sin(2.0 * pi / kSphereSegments) * 0.999);
}

TEST(ShapeOutlines, CylinderIsTheInscribedPrism) {
  const double r = 0.2, l = 0.5, pi = std::numbers::pi;
  const ShapeOutline outline = cylinder_outline(Cylinder{r, l}, {});
  expect_closed(outline);
  for (const Eigen::Vector3d& p : outline.points) {
    EXPECT_NEAR(std::hypot(p.x(), p.y()), r, 1e-15);
    EXPECT_NEAR(std::abs(p.z()), l, 0.0);
  }
  // The regular prism: base area n r² sin(2π/n) / 2, height 2l.
  EXPECT_NEAR(signed_volume(outline), 0.5 * kSphereSegments * r * r * std::sin(2.0 * pi / kSphereSegments) * 2.0 * l,
              1e-15);
}

TEST(ShapeOutlines, ConvexAndMeshAreTheirOwnTriangles) {
  // A tetrahedron with outward counter-clockwise faces: volume 1/6.
  Convex tetrahedron;
  tetrahedron.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tetrahedron.faces = {{{0, 2, 1}}, {{0, 1, 3}}, {{0, 3, 2}}, {{1, 2, 3}}};
  const ShapeOutline outline = convex_outline(tetrahedron, {});
  expect_closed(outline);
  EXPECT_NEAR(signed_volume(outline), 1.0 / 6.0, 1e-15);
  TriangleMesh mesh;
  mesh.vertices = tetrahedron.vertices;
  mesh.triangles = tetrahedron.faces;
  EXPECT_EQ(mesh_outline(mesh, {}).polygons, outline.polygons);
}

TEST(ShapeOutlines, TheVariantGivesItsAlternativesOutline) {
  const Box box{Eigen::Vector3d(0.1, 0.2, 0.3)};
  EXPECT_EQ(shape_outline(Shape{box}, {}).points, box_outline(box, {}).points);
  EXPECT_EQ(shape_outline(Shape{Sphere{0.4}}, {}).points, sphere_outline(Sphere{0.4}, {}).points);
  EXPECT_EQ(shape_outline(Shape{Halfspace{}}, {}).points, halfspace_outline(Halfspace{}, {}).points);
}

}  // namespace
}  // namespace csim
