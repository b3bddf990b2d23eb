// Narrow phase of CollisionWorld (internal: included by collision_world.cpp and the tests only, never
// by a public header, because it exposes FCL types).
//
// One function per shape pair, MuJoCo-style, in a table indexed by the Shape variant index
// (Sphere < Box < Capsule < Cylinder < Convex < TriangleMesh < Halfspace). The pair functions share pair_query.h. Each function is written for its canonical order; a pair met in the
// other order is computed swapped and then flipped (points exchanged, normal negated).
//
// Who computes what (lengths in m):
//   sphere–sphere     closed form (exact; FCL's own sphere–sphere routine is the same formula).
//   sphere–box        FCL: fcl::distance when separated (FCL's exact sphere–box distance), fcl::collide
//                     with contacts when penetrating (FCL's sphere–box intersection: depth + normal).
//   box–box           FCL names the normal: fcl::collide (ODE's SAT box–box) when penetrating or
//                     touching, fcl::distance (GJK, libccd) when separated. Where a face of either box
//                     lies along it, the clipping of convex_manifold.h gives the manifold (up to 4
//                     points, 2 in plane scenes; it says why not FCL's), even of one point (a vertex
//                     with its exact gap), and two parallel edges give their overlap's ends; crossed
//                     edges keep FCL's single point.
//   box, capsule, cylinder and convex hull with each other (box–box aside)
//                     FCL: GJK distance when separated, its penetration query when overlapping, and
//                     a measurement at a small separation when touching (gjk_pairs.h), names the
//                     normal; where a face of either shape (a box's or hull's face, a cylinder's cap)
//                     lies along it, or two parallel segments across it (capsules' cores, cylinders'
//                     side generators, boxes' and hulls' edges), the clipping of convex_manifold.h
//                     gives up to 4 points. So a cylinder standing on a box or on a cylinder's cap, a
//                     hull's face on a box or on another hull, a capsule or a cylinder lying on a face
//                     or beside a parallel capsule or cylinder, a box's or hull's edge along a capsule's
//                     or cylinder's side. Fewer than 2 points (a vertex, an edge or a rim on a face,
//                     crossed segments, a tilted capsule or cylinder): GJK's one point (feature 0).
//   sphere with box, capsule, cylinder and convex hull (sphere–box aside)
//                     GJK as above, one point: a sphere touches at one point.
//   sphere–halfspace  closed form: FCL has no distance to a halfspace (nothing for separated pairs),
//                     and one formula on both sides of contact keeps the gap continuous through 0.
//   box–halfspace     closed form, a manifold: one point per box vertex whose gap ≤ margin (FCL's
//                     box–halfspace gives a single penetrating point and nothing when separated).
//   the convex shapes against a triangle mesh  FCL's BVH for the triangles near the shape, then per
//                     triangle the shape's feature points over it and GJK's closest points
//                     (mesh_pairs.h). A manifold.
//   capsule–, cylinder–, convex–halfspace  closed forms, manifolds (halfspace_pairs.h), for the
//                     reason of box–halfspace.
//   halfspace–halfspace, mesh–mesh, mesh–halfspace  none (all fixed).
//
// Box vertices (feature index of box–halfspace contacts), in the box frame with half extents h:
//   3D: vertex i = ((i&1 ? +1 : −1) hx, (i&2 ? +1 : −1) hy, (i&4 ? +1 : −1) hz), i = 0..7;
//   plane scenes: the 4 corners of the box's z = 0 section, i = 0..3, z = 0.
#pragma once

#include "contact/contact_point.h"
#include "contact/convex_manifold.h"
#include "contact/shape.h"

#include <fcl/geometry/collision_geometry.h>
#include <fcl/narrowphase/collision_request.h>
#include <fcl/narrowphase/collision_result.h>
#include <fcl/narrowphase/distance_request.h>
#include <fcl/narrowphase/distance_result.h>

#include <Eigen/Geometry>
#include <memory>
#include <vector>

namespace csim {

// One collision object as the narrow phase sees it. Halfspaces are normalised at registration
// (unit normal). `geometry` is FCL's copy of the shape (null for halfspaces, which FCL is not asked
// about). Not the World's ShapeInstance (a body's shape in its frame): a distinct name, since both
// are linked into the same programs (one definition rule).
struct CollisionShape {
  int id = -1;
  Shape shape;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // shape frame in world
  std::shared_ptr<fcl::CollisionGeometryd> geometry;
};

// The FCL geometry of a shape (null for a halfspace).
std::shared_ptr<fcl::CollisionGeometryd> make_fcl_geometry(const Shape& shape);

// Corner `vertex` of a box in its own frame (numbering above).
Eigen::Vector3d box_vertex(const Box& box, int vertex, bool planar);
int box_vertex_count(bool planar);

class NarrowPhase {
 public:
  explicit NarrowPhase(bool planar);

  // Appends the contacts between a and b (a.id < b.id) whose gap ≤ margin (m): keys set, normal from
  // a to b, planar projection applied, frame completed with the default direction.
  void collide(const CollisionShape& a, const CollisionShape& b, double margin,
               std::vector<ContactPoint>& out);

  // Scratch reused by the pair functions: FCL's requests and results, and the clipping's buffers (no
  // per-query setup beyond FCL's own).
  struct FclScratch {
    fcl::CollisionRequestd collision_request;
    fcl::CollisionResultd collision_result;
    fcl::DistanceRequestd distance_request;
    fcl::DistanceResultd distance_result;
    ManifoldScratch manifold;  // the clipping's buffers (convex_manifold.h)
  };

 private:
  bool planar_;
  FclScratch scratch_;
};

}  // namespace csim
