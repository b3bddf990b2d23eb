#include "contact/collision_world.h"

#include "contact/narrow_phase.h"

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/narrowphase/collision_object.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace csim {

namespace {

// An FCL collision object whose world AABB we set ourselves: the tight box of the shape widened by the
// margin (FCL's computeAABB() bounds a rotated shape by its circumscribed sphere, and has no margin).
class MarginCollisionObject : public fcl::CollisionObjectd {
 public:
  explicit MarginCollisionObject(const std::shared_ptr<fcl::CollisionGeometryd>& geometry)
      : fcl::CollisionObjectd(geometry) {}

  void set_world_aabb(const Eigen::Vector3d& centre, const Eigen::Vector3d& half_size) {
    aabb.min_ = centre - half_size;
    aabb.max_ = centre + half_size;
  }
  void set_world_bounds(const Eigen::Vector3d& lower, const Eigen::Vector3d& upper, double margin) {
    aabb.min_ = lower.array() - margin;
    aabb.max_ = upper.array() + margin;
  }
};

// Half size (m) of the world AABB of a shape other than a halfspace at `pose`.
Eigen::Vector3d world_half_size(const Shape& shape, const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d& R = pose.linear();
  if (const auto* box = std::get_if<Box>(&shape)) {
    return R.cwiseAbs() * box->half_extents;
  }
  if (const auto* capsule = std::get_if<Capsule>(&shape)) {  // the segment's box, widened by the radius
    return (capsule->half_length * R.col(2).cwiseAbs()).array() + capsule->radius;
  }
  if (const auto* cylinder = std::get_if<Cylinder>(&shape)) {
    // A disk of radius r across axis a reaches r·√(1 − a_i²) along axis i.
    const Eigen::Vector3d a = R.col(2);
    const Eigen::Vector3d disk = (Eigen::Vector3d::Ones() - a.cwiseProduct(a)).cwiseMax(0.0).cwiseSqrt();
    return cylinder->half_length * a.cwiseAbs() + cylinder->radius * disk;
  }
  // A hull or a mesh: about the shape's origin, the pose's translation.
  const std::vector<Eigen::Vector3d>* vertices = nullptr;
  if (const auto* convex = std::get_if<Convex>(&shape)) vertices = &convex->vertices;
  if (const auto* mesh = std::get_if<TriangleMesh>(&shape)) vertices = &mesh->vertices;
  if (vertices) {
    Eigen::Vector3d half = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& v : *vertices) half = half.cwiseMax((R * v).cwiseAbs());
    return half;
  }
  return Eigen::Vector3d::Constant(std::get<Sphere>(shape).radius);
}

void* id_as_user_data(int id) { return reinterpret_cast<void*>(static_cast<std::intptr_t>(id)); }
int id_of(const fcl::CollisionObjectd* object) {
  return static_cast<int>(reinterpret_cast<std::intptr_t>(object->getUserData()));
}

void check_shape(const Shape& shape, bool fixed, bool planar) {
  if (const auto* sphere = std::get_if<Sphere>(&shape)) {
    if (!(sphere->radius > 0.0)) throw std::invalid_argument("Sphere radius must be > 0");
  } else if (const auto* box = std::get_if<Box>(&shape)) {
    if (!(box->half_extents.minCoeff() > 0.0)) throw std::invalid_argument("Box half extents must be > 0");
  } else if (const auto* capsule = std::get_if<Capsule>(&shape)) {
    if (!(capsule->radius > 0.0 && capsule->half_length >= 0.0))
      throw std::invalid_argument("Capsule radius must be > 0 and half length >= 0");
  } else if (const auto* cylinder = std::get_if<Cylinder>(&shape)) {
    if (!(cylinder->radius > 0.0 && cylinder->half_length > 0.0))
      throw std::invalid_argument("Cylinder radius and half length must be > 0");
  } else if (const auto* convex = std::get_if<Convex>(&shape)) {
    if (convex->vertices.size() < 4 || convex->faces.size() < 4 || convex->polygons.size() < 4)
      throw std::invalid_argument("Convex needs a hull of at least 4 vertices and 4 faces (make_convex)");
  } else if (const auto* mesh = std::get_if<TriangleMesh>(&shape)) {
    if (mesh->triangles.empty()) throw std::invalid_argument("a TriangleMesh needs at least one triangle");
    for (const auto& t : mesh->triangles)
      for (int v : t)
        if (v < 0 || v >= static_cast<int>(mesh->vertices.size()))
          throw std::invalid_argument("a TriangleMesh's triangle names a vertex it does not have");
    if (!fixed) throw std::invalid_argument("a TriangleMesh must be on a fixed body (mesh–mesh contact is not computed)");
  } else {
    if (!(std::get<Halfspace>(shape).normal.norm() > 0.0)) {
      throw std::invalid_argument("Halfspace normal must be non-zero");
    }
    // Halfspace pairs are only formed with non-fixed objects (see collision_world.h).
    if (!fixed) throw std::invalid_argument("a Halfspace must be on a fixed body");
  }
  if (planar && (std::holds_alternative<Capsule>(shape) || std::holds_alternative<Cylinder>(shape) ||
                 std::holds_alternative<Convex>(shape) || std::holds_alternative<TriangleMesh>(shape)))
    throw std::invalid_argument("capsules, cylinders, convex hulls and triangle meshes are 3D shapes: not in a plane scene");
}

// Unit normal, offset scaled alike: the same solid, and the narrow phase may assume |n| = 1.
Shape normalised(Shape shape) {
  if (auto* halfspace = std::get_if<Halfspace>(&shape)) {
    const double norm = halfspace->normal.norm();
    halfspace->normal /= norm;
    halfspace->offset /= norm;
  }
  return shape;
}

// The nodes that a surface's geometry names (its faces, contact nodes and curve), ascending; throws on
// a node outside [0, node_count).
std::vector<int> geometry_nodes(const DeformableSurfaceGeometry& geometry, int node_count) {
  std::vector<int> nodes(geometry.contact_nodes.begin(), geometry.contact_nodes.end());
  for (const auto& segment : geometry.segments) nodes.insert(nodes.end(), segment.begin(), segment.end());
  for (const auto& triangle : geometry.triangles) nodes.insert(nodes.end(), triangle.begin(), triangle.end());
  for (const CurveSegment& c : geometry.curve) nodes.insert(nodes.end(), c.nodes.begin(), c.nodes.begin() + c.count);
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  if (!nodes.empty() && (nodes.front() < 0 || nodes.back() >= node_count))
    throw std::invalid_argument("add_deformable_surface: the geometry names a node outside the " +
                                std::to_string(node_count) + " given");
  return nodes;
}

}  // namespace

struct CollisionWorld::Impl {
  // A deformable surface: its node positions and the box that bounds them.
  struct Surface {
    DeformableSurfaceGeometry geometry;
    // The nodes the geometry names (ascending): the positions kept current and bounded. A body's
    // surface is a small part of its nodes (a 52k-DOF shoe: 0.5k of 26k), and reading every node made
    // detection O(N).
    std::vector<int> nodes;
    std::vector<Eigen::Vector3d> positions;  // m, world, by node: current on `nodes`, never read elsewhere
    std::vector<Eigen::Vector3d> normals;    // outward unit normals, by node, current on `nodes` (node contacts)
    Eigen::Vector3d lower, upper;            // m, the box of `nodes` (2D: extruded to z = ±½)
    std::vector<std::pair<int, SurfaceFeatures>> features_of_body;  // bodies not listed: nodes

    SurfaceFeatures features(int body) const {
      for (const auto& [b, f] : features_of_body)
        if (b == body) return f;
      return SurfaceFeatures::nodes;
    }
  };

  struct Object {
    CollisionShape instance;
    int body = -1;
    bool fixed = false;
    std::unique_ptr<MarginCollisionObject> fcl_object;  // null for halfspaces (kept out of the tree)
    std::unique_ptr<Surface> surface;                    // deformable surfaces only
  };

  // The box of the surface's nodes: all the broad phase reads of a surface (its contacts are our closed
  // forms, deformable_surface.h). In plane scenes it spans z = ±½, as the thin shapes' boxes do.
  // The box and the node normals of the surface's current positions.
  void bound_nodes(Surface& surface) const {
    surface_node_normals(surface.positions, surface.geometry, surface.nodes, surface.normals);
    surface.lower = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    surface.upper = -surface.lower;
    for (int node : surface.nodes) {
      surface.lower = surface.lower.cwiseMin(surface.positions[node]);
      surface.upper = surface.upper.cwiseMax(surface.positions[node]);
    }
    if (planar) {
      surface.lower.z() -= 0.5;
      surface.upper.z() += 0.5;
    }
  }

  void surface_contacts(const Object& surface, const Object& shape, bool surface_is_a,
                        std::vector<ContactPoint>& out) const;

  explicit Impl(bool planar_scene)
      : planar(planar_scene),
        narrow_phase(planar_scene),
        manager(std::make_unique<fcl::DynamicAABBTreeCollisionManagerd>()) {}

  bool can_collide(int a, int b) const {
    const Object& oa = objects[a];
    const Object& ob = objects[b];
    return oa.body != ob.body && !(oa.fixed && ob.fixed) && !(oa.surface && ob.surface) &&
           (!may_touch || may_touch(oa.body, ob.body));
  }

  // Enters the objects added since the last call into the tree: FCL builds a tree of all of them at
  // once when it holds none yet (its registerObjects), and inserts them one by one otherwise.
  void register_pending() const {
    if (pending.empty()) return;
    manager->registerObjects(pending);
    pending.clear();
  }

  void refresh_aabb(Object& object) const {
    if (object.surface) {
      object.fcl_object->set_world_bounds(object.surface->lower, object.surface->upper, margin);
      return;
    }
    object.fcl_object->set_world_aabb(
        object.instance.pose.translation(),
        world_half_size(object.instance.shape, object.instance.pose).array() + margin);
  }

  // Whether the tree can hold a pair: with one object or none (a shoe, a block or a pad over a
  // halfspace) its update and query are skipped, the halfspace pairs being formed without it.
  bool tree_pairs() const { return objects_in_tree >= 2; }
  void gather_candidate_pairs() const;
  static bool gather_pair(fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* data);

  bool planar;
  double margin = 0.0;  // m, of the last update()
  std::vector<Object> objects;
  std::vector<int> halfspaces;      // ids, all fixed
  std::vector<int> moving_in_tree;  // ids of non-fixed spheres and boxes
  int objects_in_tree = 0;
  mutable NarrowPhase narrow_phase;
  std::unique_ptr<fcl::DynamicAABBTreeCollisionManagerd> manager;
  mutable std::vector<fcl::CollisionObjectd*> pending;  // added, not yet in the tree (register_pending)
  std::function<bool(int, int)> may_touch;              // set_body_filter's
  mutable std::vector<std::pair<int, int>> candidates;  // (lower id, higher id), scratch
};

// FCL's pair callback (data: the Impl); returning false asks the manager for the remaining pairs.
bool CollisionWorld::Impl::gather_pair(fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2,
                                       void* data) {
  const auto& world = *static_cast<const Impl*>(data);
  const int a = id_of(o1);
  const int b = id_of(o2);
  if (world.can_collide(a, b)) world.candidates.emplace_back(std::min(a, b), std::max(a, b));
  return false;
}

void CollisionWorld::Impl::gather_candidate_pairs() const {
  candidates.clear();
  register_pending();
  if (tree_pairs()) manager->collide(const_cast<Impl*>(this), &gather_pair);
  // Halfspaces have infinite AABBs, which FCL 0.7's DynamicAABBTree cannot hold (its tree build and
  // rebalancing crash on them), so each is paired with every moving object directly; the pair
  // function culls far objects exactly and cheaply.
  for (int h : halfspaces) {
    for (int m : moving_in_tree) {
      if (can_collide(h, m)) candidates.emplace_back(std::min(h, m), std::max(h, m));
    }
  }
  // The manager reports pairs in hash-table order: sort for deterministic results.
  std::sort(candidates.begin(), candidates.end());
}

CollisionWorld::CollisionWorld(bool planar) : impl_(std::make_unique<Impl>(planar)) {}

CollisionWorld::~CollisionWorld() = default;

int CollisionWorld::add_object(int body, const Shape& shape, bool fixed) {
  check_shape(shape, fixed, impl_->planar);
  const int id = object_count();
  Impl::Object& object = impl_->objects.emplace_back();
  object.instance.id = id;
  object.instance.shape = normalised(shape);
  object.instance.geometry = make_fcl_geometry(shape);
  object.body = body;
  object.fixed = fixed;
  if (std::holds_alternative<Halfspace>(shape)) {
    impl_->halfspaces.push_back(id);
    return id;
  }
  object.fcl_object = std::make_unique<MarginCollisionObject>(object.instance.geometry);
  object.fcl_object->setUserData(id_as_user_data(id));
  impl_->refresh_aabb(object);
  impl_->pending.push_back(object.fcl_object.get());
  ++impl_->objects_in_tree;
  if (!fixed) impl_->moving_in_tree.push_back(id);
  return id;
}

void CollisionWorld::set_pose(int object, const Eigen::Isometry3d& pose) {
  Impl::Object& o = impl_->objects.at(object);
  o.instance.pose = pose;
  if (o.fcl_object) o.fcl_object->setTransform(pose);
}

void CollisionWorld::update(double margin) {
  // A negative margin would let FCL's penetrating contacts (not filtered by margin) through.
  if (!(margin >= 0.0)) throw std::invalid_argument("margin must be >= 0");
  impl_->margin = margin;
  if (!impl_->tree_pairs()) return;  // the tree's AABBs serve its own pairs only
  for (Impl::Object& object : impl_->objects) {
    if (object.fcl_object) impl_->refresh_aabb(object);
  }
  impl_->register_pending();
  impl_->manager->update();
}

void CollisionWorld::set_body_filter(std::function<bool(int, int)> may_touch) {
  impl_->may_touch = std::move(may_touch);
}

void CollisionWorld::find_contacts(std::vector<ContactPoint>& out) const {
  out.clear();
  impl_->gather_candidate_pairs();
  for (const auto& [a, b] : impl_->candidates) {
    const Impl::Object& oa = impl_->objects[a];
    const Impl::Object& ob = impl_->objects[b];
    if (oa.surface) impl_->surface_contacts(oa, ob, true, out);
    else if (ob.surface) impl_->surface_contacts(ob, oa, false, out);
    else impl_->narrow_phase.collide(oa.instance, ob.instance, impl_->margin, out);
  }
  // Pairs come sorted and features ascend within a pair, so this only guards that invariant.
  const auto by_key = [](const ContactPoint& x, const ContactPoint& y) { return x.key < y.key; };
  if (!std::is_sorted(out.begin(), out.end(), by_key)) std::sort(out.begin(), out.end(), by_key);
}

void CollisionWorld::Impl::surface_contacts(const Object& surface, const Object& shape, bool surface_is_a,
                                           std::vector<ContactPoint>& out) const {
  const std::size_t begin = out.size();
  const Surface& s = *surface.surface;
  const SurfaceFeatures features = s.features(shape.body);
  if (features == SurfaceFeatures::smoothed)
    curve_shape_contacts(s.positions, s.geometry, shape.instance.shape, shape.instance.pose, margin, surface_is_a,
                         planar, static_cast<int>(s.positions.size()), out);
  if (features == SurfaceFeatures::faces || features == SurfaceFeatures::both)
    shape_face_contacts(s.positions, s.geometry, shape.instance.shape, shape.instance.pose, margin, surface_is_a,
                        planar, out);
  if (features == SurfaceFeatures::nodes || features == SurfaceFeatures::both)
    for (int node : s.geometry.contact_nodes)
      node_shape_contact(s.positions[node], node, s.normals[node], shape.instance.shape, shape.instance.pose, margin,
                         surface_is_a, planar, out);
  for (std::size_t i = begin; i < out.size(); ++i) {
    out[i].key.object_a = surface_is_a ? surface.instance.id : shape.instance.id;
    out[i].key.object_b = surface_is_a ? shape.instance.id : surface.instance.id;
    complete_frame(out[i], planar);
  }
}

int CollisionWorld::add_deformable_surface(int body, const std::vector<Eigen::Vector3d>& node_positions,
                                           const DeformableSurfaceGeometry& geometry) {
  const int id = object_count();
  Impl::Object& object = impl_->objects.emplace_back();
  object.instance.id = id;
  object.body = body;
  object.surface = std::make_unique<Impl::Surface>();
  Impl::Surface& surface = *object.surface;
  surface.geometry = geometry;
  surface.positions = node_positions;
  surface.nodes = geometry_nodes(geometry, static_cast<int>(node_positions.size()));
  impl_->bound_nodes(surface);
  // FCL's object needs a geometry, which nothing queries: the manager reads the box set by refresh_aabb.
  object.fcl_object = std::make_unique<MarginCollisionObject>(std::make_shared<fcl::Sphered>(0.0));
  object.fcl_object->setUserData(id_as_user_data(id));
  impl_->refresh_aabb(object);
  impl_->pending.push_back(object.fcl_object.get());
  ++impl_->objects_in_tree;
  impl_->moving_in_tree.push_back(id);
  return id;
}

void CollisionWorld::set_surface_features(int surface_object, int body, SurfaceFeatures features) {
  Impl::Object& o = impl_->objects.at(surface_object);
  if (!o.surface) throw std::invalid_argument("set_surface_features: object is not a deformable surface");
  auto& list = o.surface->features_of_body;
  std::erase_if(list, [body](const auto& item) { return item.first == body; });
  list.emplace_back(body, features);
}

void CollisionWorld::set_node_positions(int object, const std::vector<Eigen::Vector3d>& node_positions) {
  Impl::Object& o = impl_->objects.at(object);
  if (!o.surface) throw std::invalid_argument("set_node_positions: object is not a deformable surface");
  Impl::Surface& surface = *o.surface;
  if (node_positions.size() != surface.positions.size())
    throw std::invalid_argument("set_node_positions: " + std::to_string(node_positions.size()) + " positions for " +
                                std::to_string(surface.positions.size()) + " nodes");
  for (int node : surface.nodes) surface.positions[node] = node_positions[node];
  impl_->bound_nodes(surface);
}


const std::vector<int>& CollisionWorld::surface_nodes(int object) const {
  const Impl::Object& o = impl_->objects.at(object);
  if (!o.surface) throw std::invalid_argument("surface_nodes: object is not a deformable surface");
  return o.surface->nodes;
}

int CollisionWorld::object_count() const { return static_cast<int>(impl_->objects.size()); }

}  // namespace csim
