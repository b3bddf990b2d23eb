// Contact of a deformable surface (the boundary of a finite-element body) with rigid shapes.
//
// The features are the surface's nodes (node-to-surface contact against rigid shapes; feature = node
// index): their gaps, normals and closest points are closed forms of ours (point–halfspace,
// point–sphere, point–box), exact where FCL would only give a penetration depth between whole shapes.
// FCL does the broad phase: the surface's triangles form a BVHModel<OBBRSS> refitted at every update
// (beginUpdateModel / updateSubModel / endUpdateModel, then computeLocalAABB and the object's AABB,
// then the manager's update: without all of these the broad phase silently misses contacts).
// In plane scenes the boundary edges are extruded by ±½ along z into thin quads (two triangles), so
// that FCL's 3D tree holds them; nodes and normals stay in z = 0.
#pragma once

#include "contact/contact_point.h"
#include "contact/shape.h"

#include <Eigen/Geometry>
#include <array>
#include <vector>

namespace csim {

struct DeformableSurfaceGeometry {
  // Boundary segments (2D: node pairs) or triangles (3D: node triples), outward order.
  std::vector<std::array<int, 3>> triangles;   // 3D
  std::vector<std::array<int, 2>> segments;    // 2D
  std::vector<int> contact_nodes;              // the nodes that may touch (sorted)
};

// The contacts of node `node` at world position x with a rigid shape at `pose` (gap ≤ margin),
// oriented from the lower object id to the higher: surface_is_a says which is the surface.
// The surface side's point is the node itself, the shape side's the closest point on its surface.
void node_shape_contact(const Eigen::Vector3d& x, int node, const Shape& shape, const Eigen::Isometry3d& pose,
                        double margin, bool surface_is_a, bool planar, std::vector<ContactPoint>& out);

}  // namespace csim
