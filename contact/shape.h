// Collision shapes in their body's frame (metres). A shape is attached to a body at a local pose.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <variant>
#include <vector>

namespace csim {

struct Sphere {
  double radius = 0.0;  // m, > 0 (in a plane scene: a disk of that radius in z = 0)
};

struct Box {
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  // m, > 0 (plane scenes: z extent is the depth)
};

// The points within `radius` of the segment from (0, 0, −half_length) to (0, 0, +half_length) of the
// shape frame: a cylinder of length 2·half_length along local z closed by two hemispheres (FCL's
// Capsule, whose lz = 2·half_length). 3D scenes only.
struct Capsule {
  double radius = 0.0;       // m, > 0
  double half_length = 0.0;  // m, ≥ 0 (0: a sphere)
};

// The solid circular cylinder of `radius` about local z, from z = −half_length to z = +half_length
// (FCL's Cylinder, lz = 2·half_length). 3D scenes only.
struct Cylinder {
  double radius = 0.0;       // m, > 0
  double half_length = 0.0;  // m, > 0
};

// A face of a convex hull: the polygon of its coplanar triangles (shape frame).
struct ConvexFace {
  std::vector<int> vertices;                            // indices into Convex::vertices, counter-clockwise seen from outside
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();     // outward, unit
  double area = 0.0;                                    // m²
};

// The convex hull of `vertices` (shape frame, m), with its boundary as triangles `faces` (indices into
// vertices, counter-clockwise seen from outside). Built by make_convex (contact/convex_hull.h), which
// keeps only the hull's vertices and derives `polygons` and `edges` from the triangles once, so that a
// contact query (contact/support_features.h) reads them rather than merging triangles again. 3D
// scenes only.
struct Convex {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> faces;
  std::vector<ConvexFace> polygons;           // the faces, coplanar triangles merged
  std::vector<std::array<int, 2>> edges;      // the polygons' edges, each once (lower index first), sorted
};

// A one-sided surface of triangles (shape frame, m): each triangle counter-clockwise seen from the
// side that bodies meet (its outward normal (v1 − v0) × (v2 − v0)). Always on a fixed body (a
// terrain); bodies touch it from the side its triangles face, no deeper than their own size
// (mesh_pairs.h). 3D scenes only.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
};

// The solid { x : n·x ≤ offset } in the shape frame: material below the boundary plane, outward
// normal n (unit). Used for grounds and walls; always on a fixed body.
struct Halfspace {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;  // m
};

// Halfspace last: the narrow phase's pair table (narrow_phase.h) is indexed by this order, and every
// X–halfspace function takes the halfspace second.
using Shape = std::variant<Sphere, Box, Capsule, Cylinder, Convex, TriangleMesh, Halfspace>;

}  // namespace csim
