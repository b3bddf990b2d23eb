// A convex shape (sphere, box, capsule, cylinder, convex hull) against a triangle mesh (a terrain on a
// fixed body), internal to contact/ (pair_query.h).
//
// Candidates: FCL's BVH of the mesh (BVHModel<OBBRSS>) collided with a sphere about the shape's local
// box, widened by the margin: every triangle that comes within the margin of the shape's bounding
// sphere. For each candidate triangle t, ascending, with K = the shape's feature points + 1:
//   features t·K + k, k < K − 1: the shape's feature points whose projection on the triangle's plane
//     falls inside it, with their exact gap above the plane, as against a halfspace
//     (halfspace_pairs.h): a box's or a hull's vertices (material, with their arm), a capsule's two
//     cap centres less its radius, a cylinder's rim points while its axis is within 45° of the
//     triangle's normal. A box resting on a flat terrain rests on its vertices, as on a halfspace.
//   feature t·K + K − 1: the closest points of the shape and the triangle (given to FCL as a flat
//     convex hull of its corners: FCL 0.7's distance table has no entry for its TriangleP), by GJK with
//     the separation of gjk_pairs.h (a sphere's contact, a box's edge across a ridge).
// A feature point more than its shape's bounding radius below a triangle's plane is taken as being
// on the other side of the surface and ignored. Points of adjacent coplanar triangles may coincide
// (a sphere on a shared edge): redundant rows, which the contact solver shares out.
#pragma once

#include "contact/pair_query.h"

namespace csim {

void shape_mesh(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
                std::vector<ContactPoint>& out);

}  // namespace csim
