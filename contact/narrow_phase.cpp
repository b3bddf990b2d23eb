#include "contact/narrow_phase.h"

#include "contact/convex_manifold.h"
#include "contact/gjk_pairs.h"
#include "contact/halfspace_pairs.h"
#include "contact/mesh_pairs.h"
#include "contact/pair_query.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <variant>

namespace csim {

namespace {

static_assert(std::is_same_v<std::variant_alternative_t<0, Shape>, Sphere> &&
                  std::is_same_v<std::variant_alternative_t<1, Shape>, Box> &&
                  std::is_same_v<std::variant_alternative_t<2, Shape>, Capsule> &&
                  std::is_same_v<std::variant_alternative_t<3, Shape>, Cylinder> &&
                  std::is_same_v<std::variant_alternative_t<4, Shape>, Convex> &&
                  std::is_same_v<std::variant_alternative_t<5, Shape>, TriangleMesh> &&
                  std::is_same_v<std::variant_alternative_t<6, Shape>, Halfspace>,
              "the pair table below is indexed by Shape's alternative order");

// Below this separation (m) GJK's witness points (each good to ~1e-16 m) no longer give the normal to
// ~1e-9: touching boxes take their normal from FCL's SAT instead (see touching_box_box).
constexpr double kTouchingGap = 1e-6;
// How far (m) touching boxes are pushed into each other to let the SAT name the contact axis.
constexpr double kProbeDepth = 1e-5;

// FCL's deepest penetration point as a contact (pos is FCL's midpoint between the two surfaces), the
// second shape taken at `second_pose`.
bool add_deepest_fcl_contact(const CollisionShape& first, const CollisionShape& second,
                             const Eigen::Isometry3d& second_pose, PairQuery& query,
                             std::vector<ContactPoint>& out) {
  auto& result = query.fcl.collision_result;
  result.clear();
  fcl::collide(first.geometry.get(), first.pose, second.geometry.get(), second_pose,
               query.fcl.collision_request, result);
  if (result.numContacts() == 0) return false;
  const fcl::Contactd& contact = result.getContact(0);  // num_max_contacts = 1: the deepest
  const double depth = contact.penetration_depth;
  const Eigen::Vector3d n = contact.normal;
  add_contact(contact.pos + 0.5 * depth * n, contact.pos - 0.5 * depth * n, n, -depth, 0, out);
  return true;
}

// FCL's separation distance (≥ 0), or a negative value when FCL finds the shapes overlapping.
double fcl_distance(const CollisionShape& first, const CollisionShape& second, PairQuery& query) {
  auto& result = query.fcl.distance_result;
  result.clear();
  fcl::distance(first.geometry.get(), first.pose, second.geometry.get(), second.pose,
                query.fcl.distance_request, result);
  return result.min_distance;
}

void sphere_sphere(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
                   std::vector<ContactPoint>& out) {
  const double r1 = std::get<Sphere>(first.shape).radius;
  const double r2 = std::get<Sphere>(second.shape).radius;
  const Eigen::Vector3d c1 = first.pose.translation();
  const Eigen::Vector3d c2 = second.pose.translation();
  const Eigen::Vector3d delta = c2 - c1;
  const double distance = delta.norm();
  const double gap = distance - r1 - r2;
  if (gap > query.margin) return;
  // Concentric spheres have no preferred direction; any fixed one keeps the result deterministic.
  const Eigen::Vector3d n = distance > 0.0 ? Eigen::Vector3d(delta / distance) : Eigen::Vector3d::UnitX();
  add_contact(c1 + r1 * n, c2 - r2 * n, n, gap, 0, out);
}

void sphere_box(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
                std::vector<ContactPoint>& out) {
  const double gap = fcl_distance(first, second, query);
  if (gap < 0.0) {  // FCL's sphere–box distance only proves separation; -1 means overlapping
    add_deepest_fcl_contact(first, second, second.pose, query, out);
    return;
  }
  if (gap > query.margin) return;
  const auto& result = query.fcl.distance_result;
  const Eigen::Vector3d& on_sphere = result.nearest_points[0];
  const Eigen::Vector3d& on_box = result.nearest_points[1];
  // From the centre rather than between the witness points: |on_box − centre| ≥ radius, so the
  // direction stays well conditioned as the gap closes.
  const Eigen::Vector3d n = (on_box - first.pose.translation()).normalized();
  add_contact(on_sphere, on_box, n, gap, 0, out);
}

// Boxes closer than kTouchingGap: push the second into the first and let FCL's SAT name the contact
// normal. The push goes along GJK's (roughly right) witness direction, or along the line of centres
// when GJK has none (that line has a positive component on any separating normal of two convex
// bodies).
void touching_box_box(const CollisionShape& first, const CollisionShape& second, double gjk_gap,
                      PairQuery& query, std::vector<ContactPoint>& out) {
  const auto& witness = query.fcl.distance_result.nearest_points;
  const Eigen::Vector3d witness_direction = witness[1] - witness[0];
  const Eigen::Vector3d centres = second.pose.translation() - first.pose.translation();
  Eigen::Vector3d u = Eigen::Vector3d::UnitX();
  if (gjk_gap > 0.0 && witness_direction.norm() > 0.0) {
    u = witness_direction.normalized();
  } else if (centres.norm() > 0.0) {
    u = centres.normalized();
  }
  Eigen::Isometry3d pushed = second.pose;
  pushed.translation() -= kProbeDepth * u;
  const std::size_t before = out.size();
  if (!add_deepest_fcl_contact(first, second, pushed, query, out)) {
    // Not reached for a push deeper than the gap along a direction near the normal; keep GJK's.
    add_contact(witness[0], witness[0] + std::max(gjk_gap, 0.0) * u, u, std::max(gjk_gap, 0.0), 0,
                out);
    return;
  }
  // Undo the push: the second box's point moves back by kProbeDepth·u, the gap grows by
  // kProbeDepth·(u·n); the first box's point is then the second's less the (tiny) gap.
  ContactPoint& c = out[before];
  c.point_b += kProbeDepth * u;
  c.gap = gjk_gap >= 0.0 ? gjk_gap : c.gap + kProbeDepth * u.dot(c.normal);
  c.point_a = c.point_b - c.gap * c.normal;
}

// FCL's one point: the deepest when overlapping (SAT), the touching one, or GJK's closest points.
void box_box_point(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
                   std::vector<ContactPoint>& out) {
  if (add_deepest_fcl_contact(first, second, second.pose, query, out)) return;
  const double gap = fcl_distance(first, second, query);
  if (gap > query.margin) return;
  if (gap < kTouchingGap) {  // includes GJK reporting overlap where the SAT did not
    touching_box_box(first, second, gap, query, out);
    return;
  }
  const auto& result = query.fcl.distance_result;
  const Eigen::Vector3d& p1 = result.nearest_points[0];
  const Eigen::Vector3d& p2 = result.nearest_points[1];
  add_contact(p1, p2, (p2 - p1).normalized(), gap, 0, out);
}

// Replaces FCL's single point, the last of `out`, by the clipping manifold along its normal
// (convex_manifold.h) where that gives at least `min_points` points.
void replace_by_manifold(const CollisionShape& first, const CollisionShape& second, PairQuery& query, bool planar,
                         int min_points, std::vector<ContactPoint>& out) {
  const ContactPoint point = out.back();
  out.pop_back();
  if (convex_manifold(first.shape, first.pose, second.shape, second.pose, point.normal, query.margin, planar,
                      min_points, query.fcl.manifold, out) == 0)
    out.push_back(point);
}

// FCL's point names the normal; where a face lies along it, the clipping gives the manifold, even of
// one point (a box's vertex, with its exact gap and arm); an edge–edge contact keeps FCL's point.
template <bool kPlanar>
void box_box(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
             std::vector<ContactPoint>& out) {
  const std::size_t before = out.size();
  box_box_point(first, second, query, out);
  if (out.size() > before) replace_by_manifold(first, second, query, kPlanar, 1, out);
}

// GJK's point names the normal; a face or two parallel segments along it give the manifold, when it
// has two points or more; otherwise GJK's point stays (a vertex, an edge or a rim on a face, crossed
// segments, round on round).
void convex_pair(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
                 std::vector<ContactPoint>& out) {
  const std::size_t before = out.size();
  gjk_pair(first, second, query, out);
  if (out.size() > before) replace_by_manifold(first, second, query, false, 2, out);
}

void sphere_halfspace(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
                      std::vector<ContactPoint>& out) {
  const double r = std::get<Sphere>(first.shape).radius;
  const WorldPlane plane = world_plane(second);
  const Eigen::Vector3d c = first.pose.translation();
  const double gap = plane.normal.dot(c) - plane.offset - r;
  if (gap > query.margin) return;
  const Eigen::Vector3d on_sphere = c - r * plane.normal;
  // The sphere looks into the halfspace: normal −n; the plane point is on_sphere's projection.
  add_contact(on_sphere, on_sphere - gap * plane.normal, -plane.normal, gap, 0, out);
}

template <bool kPlanar>
void box_halfspace(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
                   std::vector<ContactPoint>& out) {
  const Box& box = std::get<Box>(first.shape);
  const WorldPlane plane = world_plane(second);
  const Eigen::Matrix3d& R = first.pose.linear();
  const Eigen::Vector3d c = first.pose.translation();
  const double centre_height = plane.normal.dot(c) - plane.offset;
  // Lowest vertex height, exact: skips the vertex loop for boxes well above the plane.
  const Eigen::Vector3d n_box = R.transpose() * plane.normal;
  double reach = box.half_extents.x() * std::abs(n_box.x()) + box.half_extents.y() * std::abs(n_box.y());
  if (!kPlanar) reach += box.half_extents.z() * std::abs(n_box.z());
  if (centre_height - reach > query.margin) return;

  for (int i = 0; i < box_vertex_count(kPlanar); ++i) {
    const Eigen::Vector3d arm = R * box_vertex(box, i, kPlanar);  // a vertex is a material point of the box
    const Eigen::Vector3d vertex = arm + c;                           // pose * vertex, to the bit
    const double gap = plane.normal.dot(vertex) - plane.offset;
    if (gap > query.margin) continue;
    add_contact(vertex, vertex - gap * plane.normal, -plane.normal, gap, i, out);
    out.back().arm_a = arm;
  }
}

// [planar][first type][second type], first type ≤ second type. Capsules, cylinders, hulls and meshes
// are 3D only (CollisionWorld refuses them in a plane scene); meshes and halfspaces are fixed, so never
// meet each other.
constexpr PairFunction kPairTable[2][7][7] = {
    {{sphere_sphere, sphere_box, gjk_pair, gjk_pair, gjk_pair, shape_mesh, sphere_halfspace},
     {nullptr, box_box<false>, convex_pair, convex_pair, convex_pair, shape_mesh, box_halfspace<false>},
     {nullptr, nullptr, convex_pair, convex_pair, convex_pair, shape_mesh, capsule_halfspace},
     {nullptr, nullptr, nullptr, convex_pair, convex_pair, shape_mesh, cylinder_halfspace},
     {nullptr, nullptr, nullptr, nullptr, convex_pair, shape_mesh, convex_halfspace},
     {nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr},
     {nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr}},
    {{sphere_sphere, sphere_box, nullptr, nullptr, nullptr, nullptr, sphere_halfspace},
     {nullptr, box_box<true>, nullptr, nullptr, nullptr, nullptr, box_halfspace<true>},
     {nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr},
     {nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr},
     {nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr},
     {nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr},
     {nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr}},
};

void flip(ContactPoint& c) {
  std::swap(c.point_a, c.point_b);
  std::swap(c.arm_a, c.arm_b);
  c.normal = -c.normal;
}

// Plane scenes: FCL works in 3D, so clear the rounding (or depth-direction) part out of the plane.
void project_to_plane(ContactPoint& c) {
  c.normal.z() = 0.0;
  c.normal.normalize();
  c.point_a.z() = 0.0;
  c.point_b.z() = 0.0;
  if (c.has_arm_a()) c.arm_a.z() = 0.0;
  if (c.has_arm_b()) c.arm_b.z() = 0.0;
}

}  // namespace

std::shared_ptr<fcl::CollisionGeometryd> make_fcl_geometry(const Shape& shape) {
  // Each with its local box computed (aabb_center, aabb_radius): mesh_pairs.cpp reads it.
  std::shared_ptr<fcl::CollisionGeometryd> geometry;
  if (const auto* sphere = std::get_if<Sphere>(&shape)) {
    geometry = std::make_shared<fcl::Sphered>(sphere->radius);
  } else if (const auto* box = std::get_if<Box>(&shape)) {
    geometry = std::make_shared<fcl::Boxd>(2.0 * box->half_extents);  // FCL takes full side lengths
  } else if (const auto* capsule = std::get_if<Capsule>(&shape)) {
    geometry = std::make_shared<fcl::Capsuled>(capsule->radius, 2.0 * capsule->half_length);
  } else if (const auto* cylinder = std::get_if<Cylinder>(&shape)) {
    geometry = std::make_shared<fcl::Cylinderd>(cylinder->radius, 2.0 * cylinder->half_length);
  }
  if (geometry) {
    geometry->computeLocalAABB();
    return geometry;
  }
  if (const auto* mesh = std::get_if<TriangleMesh>(&shape)) {
    auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
    std::vector<fcl::Triangle> triangles;
    for (const auto& t : mesh->triangles) triangles.emplace_back(t[0], t[1], t[2]);
    model->beginModel();
    model->addSubModel(mesh->vertices, triangles);
    model->endModel();
    model->computeLocalAABB();
    return model;
  }
  if (const auto* convex = std::get_if<Convex>(&shape)) {
    // FCL's faces: for each, its vertex count then its vertex indices.
    auto faces = std::make_shared<std::vector<int>>();
    for (const auto& f : convex->faces) faces->insert(faces->end(), {3, f[0], f[1], f[2]});
    auto hull = std::make_shared<fcl::Convexd>(std::make_shared<const std::vector<Eigen::Vector3d>>(convex->vertices),
                                               static_cast<int>(convex->faces.size()), faces);
    hull->computeLocalAABB();  // mesh_pairs.cpp reads the local box
    return hull;
  }
  return nullptr;
}

Eigen::Vector3d box_vertex(const Box& box, int vertex, bool planar) {
  const Eigen::Vector3d& h = box.half_extents;
  return {(vertex & 1) ? h.x() : -h.x(), (vertex & 2) ? h.y() : -h.y(),
          planar ? 0.0 : ((vertex & 4) ? h.z() : -h.z())};
}

int box_vertex_count(bool planar) { return planar ? 4 : 8; }

NarrowPhase::NarrowPhase(bool planar) : planar_(planar) {
  scratch_.collision_request.enable_contact = true;
  scratch_.collision_request.num_max_contacts = 1;  // FCL keeps the deepest
  scratch_.collision_request.gjk_solver_type = fcl::GST_LIBCCD;
  scratch_.distance_request.enable_nearest_points = true;
  scratch_.distance_request.enable_signed_distance = false;
  scratch_.distance_request.gjk_solver_type = fcl::GST_LIBCCD;
}

void NarrowPhase::collide(const CollisionShape& a, const CollisionShape& b, double margin,
                          std::vector<ContactPoint>& out) {
  const bool swapped = a.shape.index() > b.shape.index();
  const CollisionShape& first = swapped ? b : a;
  const CollisionShape& second = swapped ? a : b;
  const PairFunction pair = kPairTable[planar_][first.shape.index()][second.shape.index()];
  if (pair == nullptr) return;

  const std::size_t begin = out.size();
  PairQuery query{margin, scratch_};
  pair(first, second, query, out);
  for (std::size_t i = begin; i < out.size(); ++i) {
    ContactPoint& c = out[i];
    if (swapped) flip(c);
    if (planar_) project_to_plane(c);
    c.key.object_a = a.id;
    c.key.object_b = b.id;
    // The frame depends on the normal only; a manifold's points share it.
    if (i > begin && c.normal == out[i - 1].normal) {
      c.t1 = out[i - 1].t1;
      c.t2 = out[i - 1].t2;
    } else {
      complete_frame(c, planar_);
    }
  }
}

}  // namespace csim
