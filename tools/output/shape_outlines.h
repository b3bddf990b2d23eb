// The outline of a collision shape (contact/shape.h) for ParaView: surface polygons, or lines, in the
// shape's frame (m), which body_shapes.h places at the body's pose.
//
//   Sphere     3D: a UV sphere of kSphereSegments meridians and kSphereRings parallels' bands, its
//              vertices on the sphere (triangles at the poles, quadrilaterals between); plane scenes: a
//              regular polygon of kDiskSides vertices on the circle, in z = 0.
//   Box        3D: the 8 corners (±hx, ±hy, ±hz), 6 quadrilaterals; plane scenes: the 4 corners
//              (±hx, ±hy, 0), one quadrilateral (the depth hz is not drawn).
//   Halfspace  not drawable whole: 3D: a square of half side `halfspace_half_side`, centred on the
//              boundary point nearest the shape frame's origin (offset · n); plane scenes: the boundary
//              line's segment of that half length about the same point.
//   Capsule    the sphere's UV rings split at the equator, the halves moved by ∓half_length along z
//              (the equator ring taken twice, the cylinder between them).
//   Cylinder   kSphereSegments points on each rim, the two caps and the side's quadrilaterals.
//   Convex     its hull's vertices and triangles; TriangleMesh: its vertices and triangles.
// The last four are 3D only (their scenes are refused in the plane).
//
// Polygons run counter-clockwise seen from outside the solid (from +n for a halfspace; from +z in a
// plane scene), so that ParaView's normals point out of the material.
//
// One function per alternative; shape_outline dispatches and fails to compile on an alternative that
// has none: a new shape adds its function here.
#pragma once

#include "contact/shape.h"

#include <Eigen/Geometry>
#include <vector>

namespace csim {

struct ShapeOutline {
  std::vector<Eigen::Vector3d> points;     // m, in the shape frame
  std::vector<std::vector<int>> polygons;  // indices into points
  std::vector<std::vector<int>> lines;     // polylines, indices into points
};

struct OutlineSettings {
  int dimension = 3;                 // 2: plane scene (z = 0), 3: space
  double halfspace_half_side = 1.0;  // m, > 0: the drawn patch of a halfspace (body_shapes.h sizes it)
};

constexpr int kSphereSegments = 16;  // meridians: 22.5° apart
constexpr int kSphereRings = 8;      // bands from pole to pole: 22.5° apart
constexpr int kDiskSides = 32;

ShapeOutline sphere_outline(const Sphere& sphere, const OutlineSettings& settings);
ShapeOutline box_outline(const Box& box, const OutlineSettings& settings);
ShapeOutline halfspace_outline(const Halfspace& halfspace, const OutlineSettings& settings);
ShapeOutline capsule_outline(const Capsule& capsule, const OutlineSettings& settings);
ShapeOutline cylinder_outline(const Cylinder& cylinder, const OutlineSettings& settings);
ShapeOutline convex_outline(const Convex& convex, const OutlineSettings& settings);
ShapeOutline mesh_outline(const TriangleMesh& mesh, const OutlineSettings& settings);

// The outline of whichever alternative `shape` holds.
ShapeOutline shape_outline(const Shape& shape, const OutlineSettings& settings);

}  // namespace csim
