// Structured meshes of simple shapes: rectangle (quad4, quad8), box (hexa8), annulus (quad4, quad8;
// hexa8 through annulus_mesh_3d).
//
// Every generator numbers nodes and elements deterministically (rows of nodes, then rows of elements),
// shares every node between its elements (no duplicates, also at the closing seam of the annulus) and
// orders element nodes as fem/mesh.h says (counter-clockwise, positive Jacobian). quad8 meshes are
// serendipity: mid-side nodes, no centre node.
//
// Named sets. Each side of the shape is both a node set and a face set under the same name; the face
// sets are the boundary faces (boundary_faces) whose nodes all lie on that side, in element order then
// local face order, so their outward normals point out of the shape. Corner node sets hold one node.
//   rectangle: "bottom" (y = 0), "top" (y = height), "left" (x = 0), "right" (x = width);
//              corners "bottom_left", "bottom_right", "top_left", "top_right".
//   box:       "xmin", "xmax", "ymin", "ymax", "zmin", "zmax";
//              corners "x0y0z0", "x1y0z0", "x0y1z0", "x1y1z0", "x0y0z1", … (x1 = at x = lx, etc.).
//   annulus:   "inner" (r = inner_radius), "outer" (r = outer_radius).
//   annulus_mesh_3d: "inner", "outer" (all layers), "zmin" (z = −width/2), "zmax" (z = width/2);
//              and the node set "all" (every node, e.g. to hold z for plane strain: fixed: {all: [z]}).
// Sides and corners are named in the shape's own frame, before the placement moves it.
//
// Invalid arguments (a size not finite and > 0, a division count < 1, inner ≥ outer radius, an element
// type the shape does not offer, a placement that leaves z = 0 for a plane mesh) throw FemError naming
// the function and the argument.
#pragma once

#include "fem/mesh.h"

#include <Eigen/Dense>

namespace csim {

// A rigid motion applied after generation: x' = R(angle) x + offset, R a rotation about +z.
struct Placement {
  double angle = 0.0;                                    // rad, counter-clockwise about +z
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();      // m; its z must be 0 for plane meshes
};

// The rectangle [0, width] × [0, height] (m) in z = 0, nx × ny elements (quad4 or quad8).
Mesh rectangle_mesh(double width, double height, int nx, int ny, ElementType type, const Placement& placement = {});

// The box [0, lx] × [0, ly] × [0, lz] (m), nx × ny × nz hexa8 elements.
Mesh box_mesh(double lx, double ly, double lz, int nx, int ny, int nz, const Placement& placement = {});

// The ring inner_radius ≤ r ≤ outer_radius (m) centred at the origin in z = 0: n_circumferential
// (≥ 3) elements around, n_radial across. Element edges along the circles are split at equal angles,
// the first radial edge lying on +x; quad4 corners and quad8 corner and mid-side nodes of the curved
// edges sit exactly on their circle, so quad8 represents the arcs to second order.
Mesh annulus_mesh(double inner_radius, double outer_radius, int n_circumferential, int n_radial, ElementType type,
                  const Placement& placement = {});

// The quad4 annulus above extruded along +z into the ring inner_radius ≤ r ≤ outer_radius,
// −width/2 ≤ z ≤ width/2 (m): n_axial (≥ 1) layers of hexa8 elements, centred on z = 0 (e.g. a 3D
// rolling ring, one element wide). Layer k's nodes follow layer k−1's in the plane annulus's order,
// elements go layer by layer, and each hexa8's bottom face is its quad4 (positive Jacobians). The
// curved faces are flat between the circles' nodes, as the quad4 edges are straight.
Mesh annulus_mesh_3d(double inner_radius, double outer_radius, double width, int n_circumferential, int n_radial,
                     int n_axial, const Placement& placement = {});

}  // namespace csim
