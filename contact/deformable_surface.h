// Contact of a deformable surface (the boundary of a finite-element body) with rigid shapes.
//
// Two kinds of features, chosen per pair of bodies (SurfaceFeatures):
// - node features, the surface's nodes against the rigid shape (node-to-surface contact; feature =
//   node index): gaps, normals and closest points are closed forms of ours (point–halfspace,
//   point–sphere, point–box), exact where FCL would only give a penetration depth between whole shapes;
// - face features, the rigid shape's own features against the surface's faces (a sphere's nearest
//   point, a box's vertices; feature = −1 − k): the closest point of the deformed faces (segments in
//   plane scenes, triangles in space, so quad8 edges and hexa8 faces are taken piecewise flat) and its
//   interpolation weights on the face's nodes, which give the contact's Jacobian on the nodes.
// `both` is the symmetric (two-pass) treatment: a box edge and a surface corner can both be caught;
// - smoothed features (plane scenes), Gauss points along a smooth curve through the boundary nodes
//   (boundary_curve.h: Catmull–Rom for quad4 boundaries, the quadratic edge for quad8) against the
//   rigid shape, each set like a node (feature = node_count + kCurveGaussPoints·segment + g). Against a
//   plane (a halfspace, a box face) the gap n·x(s_g) − offset is exactly linear in the nodes, with the
//   row n·Σ w_k(s_g) δx_k. The points are independent unilateral constraints, not scaled by their
//   Gauss weights: a positive factor on a row rescales its force and leaves the (rigid) Signorini–
//   Coulomb solution unchanged, and the contact solver handles the redundant rows (more points
//   than nodes). What the curve removes is the polygon's facets: its points follow the circle to
//   O(h⁴) where the nodes' chords leave a sagitta R h²/8.
// FCL does the broad phase: its manager holds each surface as one object whose box is the bounding
// box of the surface's nodes, set at every update (collision_world.cpp). Since every feature above is
// a closed form of ours, that box is all FCL reads of a surface: a BVH of the surface's faces, refitted
// at every update, gave the same box at many times the cost (the refit was 5 % of a rolling ring's
// instructions).
// In plane scenes the box spans z = ±½, like the thin shapes' boxes; nodes and normals stay in z = 0.
// The rigid shape is a sphere, a box or a halfspace: the functions below throw std::invalid_argument
// for a capsule, a cylinder, a convex hull or a mesh (the scene loader refuses such a law before the first step).
#pragma once

#include "contact/boundary_curve.h"
#include "contact/contact_point.h"
#include "contact/shape.h"

#include <Eigen/Geometry>
#include <array>
#include <vector>

namespace csim {

enum class SurfaceFeatures { nodes, faces, both, smoothed };

struct DeformableSurfaceGeometry {
  // Boundary segments (2D: node pairs) or triangles (3D: node triples), outward order.
  std::vector<std::array<int, 3>> triangles;   // 3D
  std::vector<std::array<int, 2>> segments;    // 2D
  std::vector<int> contact_nodes;              // the nodes that may touch (sorted)
  std::vector<CurveSegment> curve;             // 2D, smoothed features only (boundary_curve.h)
};

// The contacts of node `node` at world position x with a rigid shape at `pose` (gap ≤ margin),
// oriented from the lower object id to the higher: surface_is_a says which is the surface.
// The surface side's point is the node itself, the shape side's the closest point on its surface;
// inside a box (or on it within round-off, 1e-9 of its largest half extent), the point on the face
// that the surface was pressed through, chosen with surface_normal (the surface's outward unit normal
// at the node, surface_node_normals; zero when unknown: then the nearest face): at a box's edge the
// nearest face is ambiguous, and a node under a punch's edge would take the side face's normal.
void node_shape_contact(const Eigen::Vector3d& x, int node, const Eigen::Vector3d& surface_normal, const Shape& shape,
                        const Eigen::Isometry3d& pose, double margin, bool surface_is_a, bool planar,
                        std::vector<ContactPoint>& out);

// The outward unit normal of the surface at each of `nodes` (normals indexed like positions, sized to
// them; the other entries left as they were): the normalised sum of the outward normals of the faces
// that hold the node (segments in plane scenes, triangles in space), each weighted by its length or
// area; zero for a node on no face. `nodes` must hold every node of the geometry's faces.
void surface_node_normals(const std::vector<Eigen::Vector3d>& positions, const DeformableSurfaceGeometry& geometry,
                          const std::vector<int>& nodes, std::vector<Eigen::Vector3d>& normals);

// The contacts of a rigid shape's features with the surface's faces (gap ≤ margin), oriented like
// node_shape_contact. A sphere gives at most one (its point nearest the surface, feature −1), a box
// one per vertex k (feature −1 − k; the 4 in-plane corners in plane scenes, 8 vertices in space);
// halfspaces have no such features and give none. Each point is set against the closest face: outside
// the body the gap is the distance and the normal joins the two points (the face normal when they
// coincide); inside, the gap is minus the distance and the normal is the face's.
void shape_face_contacts(const std::vector<Eigen::Vector3d>& positions, const DeformableSurfaceGeometry& geometry,
                         const Shape& shape, const Eigen::Isometry3d& pose, double margin, bool surface_is_a,
                         bool planar, std::vector<ContactPoint>& out);

// The contacts of the Gauss points of the smoothed boundary (geometry.curve) with a rigid shape
// (gap ≤ margin), oriented like node_shape_contact (the curve's own normal choosing a box's face);
// feature = first_feature + kCurveGaussPoints·i + g
// for point g of segment i (first_feature: the node count, so that they never meet node features).
void curve_shape_contacts(const std::vector<Eigen::Vector3d>& positions, const DeformableSurfaceGeometry& geometry,
                          const Shape& shape, const Eigen::Isometry3d& pose, double margin, bool surface_is_a,
                          bool planar, int first_feature, std::vector<ContactPoint>& out);

}  // namespace csim
