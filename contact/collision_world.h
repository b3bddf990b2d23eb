// Contact detection with FCL: a DynamicAABBTree collision manager for the broad phase, FCL queries
// for the narrow phase, behind our own ContactPoint type (contact_point.h for the sign conventions).
//
// Contacts are wanted before they close (Moreau–Jean activation by predicted gap), so every object's
// AABB is inflated by `margin` for the broad phase and the narrow phase reports pairs whose gap is
// ≤ margin. The caller then keeps those whose predicted gap is ≤ 0.
//
// Manifolds: FCL returns one point per pair. A box resting flat on a halfspace needs its vertices, so
// box–halfspace contacts are generated per box vertex (feature = vertex index; 4 in-plane corners in
// plane scenes, 8 in 3D), each with its exact gap; so do the capsule's end caps, the cylinder's rim
// points and the convex hull's vertices against a halfspace (halfspace_pairs.h). The other pairs
// give one point (feature 0).
//
// Plane scenes (planar = true) live in z = 0 of FCL's 3D world: normals and points have z = 0.
// Objects of the same body never collide, nor do two fixed objects.
//
// Halfspaces stay out of FCL's DynamicAABBTree: their AABB is infinite, and FCL 0.7 crashes building
// or rebalancing a tree that holds one (tested in collision_world_test.cpp). Each halfspace (always
// fixed) is paired directly with every non-fixed object; the closed-form pair functions cull far
// objects exactly. Halfspace–halfspace pairs give nothing.
//
// find_contacts() is const but reuses internal scratch: one thread per CollisionWorld.
#pragma once

#include "contact/contact_point.h"
#include "contact/deformable_surface.h"
#include "contact/shape.h"

#include <Eigen/Geometry>
#include <functional>
#include <memory>
#include <vector>

namespace csim {

class CollisionWorld {
 public:
  explicit CollisionWorld(bool planar);
  ~CollisionWorld();
  CollisionWorld(const CollisionWorld&) = delete;
  CollisionWorld& operator=(const CollisionWorld&) = delete;

  // Registers a shape carried by `body` (any id of the caller's; `fixed` bodies never move).
  // Returns the object id (0, 1, 2, ... in call order). Throws std::invalid_argument for a
  // non-positive size, a zero halfspace normal, a halfspace on a non-fixed body, or a capsule,
  // cylinder or convex hull in a plane world.
  int add_object(int body, const Shape& shape, bool fixed);

  // A deformable surface (deformable_surface.h) of `body`, with its nodes' world positions (m).
  // Deformable surfaces touch rigid shapes only (not each other). Returns the object id.
  int add_deformable_surface(int body, const std::vector<Eigen::Vector3d>& node_positions,
                             const DeformableSurfaceGeometry& geometry);

  // Which features of the deformable surface `surface_object` touch the shapes of `body`
  // (deformable_surface.h); nodes unless set.
  void set_surface_features(int surface_object, int body, SurfaceFeatures features);

  // World pose of the object's shape frame. Call for the moving objects, then update().
  void set_pose(int object, const Eigen::Isometry3d& pose);
  // Current node positions of a deformable surface (all its nodes, as given to add_…); then update().
  // Only the entries of surface_nodes(object) are read.
  void set_node_positions(int object, const std::vector<Eigen::Vector3d>& node_positions);
  // The nodes a deformable surface's geometry names (its faces, contact nodes and curve), ascending.
  const std::vector<int>& surface_nodes(int object) const;

  // Which pairs of bodies may touch (the callers' contact laws); a pair of objects whose bodies it
  // refuses is dropped before the narrow phase. Unset: every pair of bodies.
  void set_body_filter(std::function<bool(int body_a, int body_b)> may_touch);

  // Refreshes AABBs (inflated by margin, m, ≥ 0) and the manager (FCL's update()). The objects added
  // since the last update enter FCL's tree here, at their poses, all at once: inserted one by one at
  // their creation (every pose the identity, every AABB the same) they built a degenerate tree, and
  // adding 2000 spheres cost 42 k instructions each.
  void update(double margin);

  // All contact points with gap ≤ margin (the margin of the last update), sorted by key.
  void find_contacts(std::vector<ContactPoint>& out) const;

  int object_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace csim
