#include "contact/convex_hull.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace csim {

namespace {

using Face = std::array<int, 3>;

// Signed distance (times the face's doubled area) of p above the face's plane: > 0 outside.
double height(const std::vector<Eigen::Vector3d>& p, const Face& f, const Eigen::Vector3d& x) {
  return (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).normalized().dot(x - p[f[0]]);
}

int farthest(const std::vector<Eigen::Vector3d>& points, auto&& distance) {
  int best = -1;
  double best_distance = -1.0;
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    const double d = distance(points[i]);
    if (d > best_distance) best_distance = d, best = i;
  }
  return best;
}

// The hull's triangles over indices of `points` (see make_convex for the checks).
std::vector<Face> hull_faces(const std::vector<Eigen::Vector3d>& points, double tolerance) {

  // The first tetrahedron: the widest one that four of the points span, greedily.
  const int a = 0;
  const int b = farthest(points, [&](const Eigen::Vector3d& x) { return (x - points[a]).norm(); });
  const Eigen::Vector3d ab = (points[b] - points[a]).normalized();
  const int c = farthest(points, [&](const Eigen::Vector3d& x) { return (x - points[a]).cross(ab).norm(); });
  const Eigen::Vector3d up = (points[b] - points[a]).cross(points[c] - points[a]);
  if (!((points[b] - points[a]).norm() > tolerance) || !(up.norm() > tolerance * (points[b] - points[a]).norm()))
    throw std::invalid_argument("a convex hull's points lie on one line: the hull has no volume");
  const Eigen::Vector3d plane_normal = up.normalized();
  const int d = farthest(points, [&](const Eigen::Vector3d& x) { return std::abs(plane_normal.dot(x - points[a])); });
  if (!(std::abs(plane_normal.dot(points[d] - points[a])) > tolerance))
    throw std::invalid_argument("a convex hull's points lie on one plane: the hull has no volume");

  std::vector<Face> faces;
  if (plane_normal.dot(points[d] - points[a]) > 0.0)  // d above abc: abc seen from outside is clockwise
    faces = {{a, c, b}, {a, b, d}, {b, c, d}, {c, a, d}};
  else
    faces = {{a, b, c}, {a, d, b}, {b, d, c}, {c, d, a}};

  std::vector<bool> visible;
  std::map<std::pair<int, int>, int> edge_face;  // directed edge → the face holding it
  for (int p = 0; p < static_cast<int>(points.size()); ++p) {
    if (p == a || p == b || p == c || p == d) continue;
    visible.assign(faces.size(), false);
    bool any = false;
    for (std::size_t f = 0; f < faces.size(); ++f)
      if (height(points, faces[f], points[p]) > tolerance) visible[f] = any = true;
    if (!any) continue;  // inside the hull or on it
    edge_face.clear();
    for (std::size_t f = 0; f < faces.size(); ++f)
      for (int k = 0; k < 3; ++k) edge_face[{faces[f][k], faces[f][(k + 1) % 3]}] = static_cast<int>(f);
    std::vector<Face> kept;
    std::vector<Face> fan;
    for (std::size_t f = 0; f < faces.size(); ++f) {
      if (!visible[f]) {
        kept.push_back(faces[f]);
        continue;
      }
      for (int k = 0; k < 3; ++k) {  // a horizon edge: its twin belongs to a face p does not see
        const int from = faces[f][k], to = faces[f][(k + 1) % 3];
        if (!visible[edge_face.at({to, from})]) fan.push_back({from, to, p});
      }
    }
    kept.insert(kept.end(), fan.begin(), fan.end());
    faces = std::move(kept);
  }

  return faces;
}

// Whether the faces about vertex v lie on at least three planes of independent normals: a corner of
// the hull. A point taken in before the corners around it (on a face's or an edge's line) has its
// faces on one or two planes.
bool is_corner(const std::vector<Eigen::Vector3d>& p, const std::vector<Face>& faces, int v) {
  constexpr double kIndependent = 1e-9;  // |n1 × n2|, |det(n1, n2, n3)| of unit normals
  std::vector<Eigen::Vector3d> normals;
  for (const Face& f : faces)
    if (f[0] == v || f[1] == v || f[2] == v)
      normals.push_back((p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).normalized());
  for (std::size_t i = 0; i < normals.size(); ++i)
    for (std::size_t j = i + 1; j < normals.size(); ++j) {
      const Eigen::Vector3d across = normals[i].cross(normals[j]);
      if (across.norm() <= kIndependent) continue;
      for (std::size_t k = j + 1; k < normals.size(); ++k)
        if (std::abs(across.dot(normals[k])) > kIndependent) return true;
    }
  return false;
}

// Adds the hull's polygons and edges (shape.h) from its triangles. A polygon is every vertex on a
// triangle's plane, within kCoplanar × the hull's extent (the construction splits a flat face into
// triangles of one plane to about 1e-10 of it, and on a convex hull the vertices on a face's plane are
// that face's), in counter-clockwise order about their mean seen from outside; the triangles of that
// plane facing the same way are taken with it. Its normal and area are Newell's (twice the area times
// the normal is the sum of the cross products of consecutive vertices about the mean).
void add_polygons(Convex& hull, double extent) {
  constexpr double kCoplanar = 1e-9;
  const std::vector<Eigen::Vector3d>& p = hull.vertices;
  const auto triangle_normal = [&](const Face& f) { return (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).normalized(); };
  std::vector<bool> taken(hull.faces.size(), false);
  for (std::size_t f = 0; f < hull.faces.size(); ++f) {
    if (taken[f]) continue;
    const Eigen::Vector3d normal = triangle_normal(hull.faces[f]);
    const Eigen::Vector3d& origin = p[hull.faces[f][0]];
    const auto on_plane = [&](int v) { return std::abs(normal.dot(p[v] - origin)) <= kCoplanar * extent; };
    for (std::size_t g = f; g < hull.faces.size(); ++g) {
      const Face& t = hull.faces[g];
      if (on_plane(t[0]) && on_plane(t[1]) && on_plane(t[2]) && triangle_normal(t).dot(normal) > 0.0) taken[g] = true;
    }
    std::vector<int> on_face;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int v = 0; v < static_cast<int>(p.size()); ++v)
      if (on_plane(v)) on_face.push_back(v), mean += p[v];
    mean /= static_cast<double>(on_face.size());
    // In-plane axes: by angle about the mean, counter-clockwise seen from outside.
    const Eigen::Vector3d u = (p[on_face[0]] - mean).normalized();
    const Eigen::Vector3d w = normal.cross(u);
    std::vector<std::pair<double, int>> by_angle;
    for (int v : on_face) by_angle.emplace_back(std::atan2(w.dot(p[v] - mean), u.dot(p[v] - mean)), v);
    std::sort(by_angle.begin(), by_angle.end());
    ConvexFace& face = hull.polygons.emplace_back();
    Eigen::Vector3d newell = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < by_angle.size(); ++k) {
      const int a = by_angle[k].second, b = by_angle[(k + 1) % by_angle.size()].second;
      face.vertices.push_back(a);
      newell += (p[a] - mean).cross(p[b] - mean);
      hull.edges.push_back({std::min(a, b), std::max(a, b)});
    }
    face.normal = newell.normalized();
    face.area = 0.5 * newell.norm();
  }
  std::sort(hull.edges.begin(), hull.edges.end());
  hull.edges.erase(std::unique(hull.edges.begin(), hull.edges.end()), hull.edges.end());
}

}  // namespace

Convex make_convex(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 4)
    throw std::invalid_argument("a convex hull needs at least 4 points (" + std::to_string(points.size()) + " given)");
  for (const Eigen::Vector3d& x : points)
    if (!x.allFinite()) throw std::invalid_argument("a convex hull's point is not finite");
  Eigen::Vector3d lower = points[0], upper = points[0];
  for (const Eigen::Vector3d& x : points) lower = lower.cwiseMin(x), upper = upper.cwiseMax(x);
  const double tolerance = 1e-10 * (upper - lower).norm();

  // The hull of the points, then again of its corners alone (see is_corner), in the order given.
  const std::vector<Face> first = hull_faces(points, tolerance);
  std::vector<int> corners;
  for (int i = 0; i < static_cast<int>(points.size()); ++i)
    if (is_corner(points, first, i)) corners.push_back(i);
  Convex hull;
  for (int i : corners) hull.vertices.push_back(points[i]);
  hull.faces = hull_faces(hull.vertices, tolerance);
  add_polygons(hull, (upper - lower).norm());
  return hull;
}

ConvexMassProperties convex_mass_properties(const Convex& convex) {
  // Each face and the first vertex o span a signed tetrahedron; their sums are the solid's integrals
  // (Tonon, J. Math. Stat. 1(1) 2004, for the second moments of a tetrahedron).
  ConvexMassProperties m;
  const Eigen::Vector3d o = convex.vertices.at(0);
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  // ∫ x xᵀ dV about o
  for (const auto& f : convex.faces) {
    const Eigen::Vector3d v1 = convex.vertices[f[0]] - o, v2 = convex.vertices[f[1]] - o,
                          v3 = convex.vertices[f[2]] - o;
    const double volume = v1.dot(v2.cross(v3)) / 6.0;
    m.volume += volume;
    m.centroid += volume * (v1 + v2 + v3) / 4.0;
    // ∫ x xᵀ over the tetrahedron (0, v1, v2, v3) = V/20 (Σ vi viᵀ + (Σ vi)(Σ vi)ᵀ).
    const Eigen::Vector3d sum = v1 + v2 + v3;
    second += volume / 20.0 * (v1 * v1.transpose() + v2 * v2.transpose() + v3 * v3.transpose() + sum * sum.transpose());
  }
  m.centroid /= m.volume;
  second -= m.volume * m.centroid * m.centroid.transpose();  // about the centroid
  m.centroid += o;
  m.inertia_per_density = second.trace() * Eigen::Matrix3d::Identity() - second;
  return m;
}

}  // namespace csim
