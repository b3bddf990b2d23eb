#include "contact/mesh_pairs.h"

#include "contact/gjk_pairs.h"
#include "contact/halfspace_pairs.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>

#include <algorithm>
#include <limits>

namespace csim {

namespace {

// A point of the shape (world, m) that may rest on a triangle, with the radius about it (a capsule's
// cap) and, for a material point, its arm from the shape's origin.
struct FeaturePoint {
  Eigen::Vector3d point;
  double radius = 0.0;
  bool material = false;
  Eigen::Vector3d arm = Eigen::Vector3d::Zero();
};

// The shape's feature points (mesh_pairs.h), for a triangle of outward normal n.
void feature_points(const CollisionShape& shape, const Eigen::Vector3d& n, std::vector<FeaturePoint>& points) {
  points.clear();
  const Eigen::Matrix3d& R = shape.pose.linear();
  const Eigen::Vector3d c = shape.pose.translation();
  const auto material = [&](const Eigen::Vector3d& local) {
    const Eigen::Vector3d arm = R * local;
    points.push_back({arm + c, 0.0, true, arm});
  };
  if (const auto* box = std::get_if<Box>(&shape.shape)) {
    for (int i = 0; i < box_vertex_count(false); ++i) material(box_vertex(*box, i, false));
  } else if (const auto* convex = std::get_if<Convex>(&shape.shape)) {
    for (const Eigen::Vector3d& v : convex->vertices) material(v);
  } else if (const auto* capsule = std::get_if<Capsule>(&shape.shape)) {
    for (double z : {-capsule->half_length, capsule->half_length})
      points.push_back({c + z * R.col(2), capsule->radius, false, Eigen::Vector3d::Zero()});
  } else if (const auto* cylinder = std::get_if<Cylinder>(&shape.shape)) {
    const bool face_down = std::abs(n.dot(R.col(2))) >= kFaceDown;
    for (int rim = 0; rim < 2; ++rim)
      for (int j = 0; j < kRimPoints; ++j) {
        if (face_down) material(cylinder_rim_point(*cylinder, rim, j));
        else points.push_back({Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()), 0.0, false,
                               Eigen::Vector3d::Zero()});
      }
  }
}

// The number of feature points of a shape (the same for every triangle: a cylinder's rim points
// that do not apply are kept as NaN placeholders, so that feature numbers stay fixed).
int feature_count(const Shape& shape) {
  if (std::holds_alternative<Box>(shape)) return box_vertex_count(false);
  if (const auto* convex = std::get_if<Convex>(&shape)) return static_cast<int>(convex->vertices.size());
  if (std::holds_alternative<Capsule>(shape)) return 2;
  if (std::holds_alternative<Cylinder>(shape)) return 2 * kRimPoints;
  return 0;
}

// Whether p's projection on the plane of triangle (a, b, c), normal n, lies inside it (edges included).
bool projects_inside(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                     const Eigen::Vector3d& c, const Eigen::Vector3d& n) {
  return n.dot((b - a).cross(p - a)) >= 0.0 && n.dot((c - b).cross(p - b)) >= 0.0 &&
         n.dot((a - c).cross(p - c)) >= 0.0;
}

}  // namespace

void shape_mesh(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
                std::vector<ContactPoint>& out) {
  const auto& mesh = std::get<TriangleMesh>(second.shape);
  const fcl::CollisionGeometryd& shape_geometry = *first.geometry;
  // The candidates: triangles that meet the shape's bounding sphere widened by the margin.
  const double reach = shape_geometry.aabb_radius + query.margin;
  const fcl::Sphered probe(reach);
  Eigen::Isometry3d probe_pose = Eigen::Isometry3d::Identity();
  probe_pose.translation() = first.pose * shape_geometry.aabb_center;
  fcl::CollisionRequestd request(std::numeric_limits<int>::max() / 2, false);
  request.gjk_solver_type = fcl::GST_LIBCCD;
  auto& result = query.fcl.collision_result;
  result.clear();
  fcl::collide(second.geometry.get(), second.pose, &probe, probe_pose, request, result);
  std::vector<int> candidates;
  for (std::size_t i = 0; i < result.numContacts(); ++i) candidates.push_back(result.getContact(i).b1);
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());

  const int K = feature_count(first.shape) + 1;
  std::vector<FeaturePoint> points;
  for (int t : candidates) {
    const auto& tri = mesh.triangles[t];
    const Eigen::Vector3d a = second.pose * mesh.vertices[tri[0]], b = second.pose * mesh.vertices[tri[1]],
                          c = second.pose * mesh.vertices[tri[2]];
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    feature_points(first, n, points);
    for (int k = 0; k < static_cast<int>(points.size()); ++k) {
      const FeaturePoint& f = points[k];
      if (std::isnan(f.point.x()) || !projects_inside(f.point, a, b, c, n)) continue;
      const double height = n.dot(f.point - a);
      const double gap = height - f.radius;
      if (gap > query.margin || height < -shape_geometry.aabb_radius - f.radius) continue;
      const Eigen::Vector3d on_shape = f.point - f.radius * n;
      add_contact(on_shape, on_shape - gap * n, -n, gap, t * K + k, out);
      if (f.material) out.back().arm_a = f.arm;
    }
    // The closest points of the shape and the triangle (GJK), the triangle about its centroid.
    const Eigen::Vector3d centroid = (a + b + c) / 3.0;
    CollisionShape triangle;
    triangle.shape = Sphere{};  // gjk_pair reads the geometry and the pose only
    triangle.pose = Eigen::Isometry3d::Identity();
    triangle.pose.translation() = centroid;
    // A flat hull of its three corners, both sides: FCL's distance table has no TriangleP entries.
    static const auto both_sides = std::make_shared<const std::vector<int>>(std::vector<int>{3, 0, 1, 2, 3, 0, 2, 1});
    triangle.geometry = std::make_shared<fcl::Convexd>(
        std::make_shared<const std::vector<Eigen::Vector3d>>(
            std::vector<Eigen::Vector3d>{a - centroid, b - centroid, c - centroid}),
        2, both_sides);
    const std::size_t before = out.size();
    gjk_pair(first, triangle, query, out);
    if (out.size() > before) {
      ContactPoint& closest = out.back();
      // The triangle's other side: a shape below its plane by more than its size is not on it.
      if (n.dot(closest.point_a - a) < -2.0 * shape_geometry.aabb_radius) out.pop_back();
      else closest.key.feature = t * K + K - 1;
    }
  }
}

}  // namespace csim
