#include "contact/deformable_surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace csim {

namespace {

// Signed distance of x to the shape (m, positive outside), the closest surface point, and the
// shape's outward unit normal there.
struct Projection {
  double distance;
  Eigen::Vector3d point, normal;
};

// How far outside a box (relative to its largest half extent) a point still counts as on it: the
// round-off of a node placed on a box's edge (x − c = 0.2000000000000002 against h = 0.2).
constexpr double kOnBoxTolerance = 1e-9;
// The least |cos| between a box face's outward normal and the surface's inward normal for the face to
// be one the surface can have been pressed through (60°): a face seen edge-on is not.
constexpr double kFacingFaces = 0.5;

// A point inside a box (or on it within kOnBoxTolerance): the face it is pushed out through. The
// nearest face is ambiguous at the box's edges: a surface node under a punch's edge lies on the side
// face's plane (depth 0) while the bottom face has pressed it by the penetration, and the nearest face
// would push it sideways (a frictionless punch would push its block sideways). With the
// surface's outward normal n_s (box frame; zero when unknown), the face is the one the surface looks at:
// among the faces whose outward normal n_f meets n_s head-on (−n_f·n_s ≥ kFacingFaces), the one where
// the ray back along −n_s leaves the box first (depth / (−n_f·n_s): the surface-normal projection of
// segment-to-segment and mortar contact). Without n_s, or when no face qualifies (a surface deeper
// than the box is wide), the nearest face. Ties go to the lower axis, for determinism.
int entry_axis(const Eigen::Vector3d& local, const Eigen::Vector3d& h, const Eigen::Vector3d& surface_normal,
               int axes) {
  int axis = -1;
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < axes; ++i) {
    const double facing = (local(i) >= 0.0 ? -1.0 : 1.0) * surface_normal(i);  // −n_f·n_s
    if (!(facing >= kFacingFaces)) continue;
    const double exit = std::max(h(i) - std::abs(local(i)), 0.0) / facing;
    if (exit < best) best = exit, axis = i;
  }
  if (axis >= 0) return axis;
  best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < axes; ++i) {
    const double to_face = h(i) - std::abs(local(i));
    if (to_face < best) best = to_face, axis = i;
  }
  return axis;
}

// surface_normal: the surface's outward unit normal at x (world), or zero when unknown.
Projection project(const Eigen::Vector3d& x, const Eigen::Vector3d& surface_normal, const Shape& shape,
                   const Eigen::Isometry3d& pose, bool planar) {
  if (const auto* halfspace = std::get_if<Halfspace>(&shape)) {
    const Eigen::Vector3d n = pose.linear() * halfspace->normal;
    const double offset = halfspace->offset + n.dot(pose.translation());
    const double d = n.dot(x) - offset;
    return {d, x - d * n, n};
  }
  if (const auto* sphere = std::get_if<Sphere>(&shape)) {
    Eigen::Vector3d r = x - pose.translation();
    if (planar) r.z() = 0.0;
    const double length = r.norm();
    const Eigen::Vector3d n = length > 0.0 ? Eigen::Vector3d(r / length) : Eigen::Vector3d::UnitY();
    return {length - sphere->radius, pose.translation() + sphere->radius * n, n};
  }
  // Box: outside, the clamped point; inside (or on it within round-off), a face (entry_axis).
  const auto* box_shape = std::get_if<Box>(&shape);
  if (!box_shape)
    throw std::invalid_argument("node-to-surface contact takes spheres, boxes and halfspaces, not a capsule, "
                                "cylinder, convex hull or mesh");
  const Box& box = *box_shape;
  Eigen::Vector3d local = pose.inverse() * x;
  Eigen::Vector3d h = box.half_extents;
  const int axes = planar ? 2 : 3;
  const double on_box = kOnBoxTolerance * h.head(axes).maxCoeff();
  if (planar) h.z() = std::numeric_limits<double>::infinity(), local.z() = 0.0;
  const Eigen::Vector3d clamped = local.cwiseMax(-h).cwiseMin(h);
  const double outside = (local - clamped).norm();
  const bool known_normal = surface_normal.squaredNorm() > 0.0;
  if (outside > (known_normal ? on_box : 0.0)) {
    const Eigen::Vector3d n = (local - clamped) / outside;
    return {outside, pose * clamped, pose.linear() * n};
  }
  const int axis = entry_axis(local, h, pose.linear().transpose() * surface_normal, axes);
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  n(axis) = local(axis) >= 0.0 ? 1.0 : -1.0;
  Eigen::Vector3d on_face = local;
  on_face(axis) = n(axis) * h(axis);
  return {-(h(axis) - std::abs(local(axis))), pose * on_face, pose.linear() * n};
}

}  // namespace

namespace {

// A contact of the surface point x (its node weights `surface`) with the shape, if gap ≤ margin.
void point_shape_contact(const Eigen::Vector3d& x, const Eigen::Vector3d& surface_normal, const SurfacePoint& surface,
                         int feature, const Shape& shape, const Eigen::Isometry3d& pose, double margin,
                         bool surface_is_a, bool planar, std::vector<ContactPoint>& out) {
  const Projection p = project(x, surface_normal, shape, pose, planar);
  if (p.distance > margin) return;
  ContactPoint& c = out.emplace_back();
  c.key.feature = feature;
  c.surface = surface;
  c.gap = p.distance;
  // The shape's outward normal points from the shape to the surface point.
  if (surface_is_a) {
    c.point_a = x;
    c.point_b = p.point;
    c.normal = -p.normal;
  } else {
    c.point_a = p.point;
    c.point_b = x;
    c.normal = p.normal;
  }
  if (planar) {
    c.normal.z() = 0.0;
    c.normal.normalize();
    c.point_a.z() = c.point_b.z() = 0.0;
  }
}

}  // namespace

void node_shape_contact(const Eigen::Vector3d& x, int node, const Eigen::Vector3d& surface_normal, const Shape& shape,
                        const Eigen::Isometry3d& pose, double margin, bool surface_is_a, bool planar,
                        std::vector<ContactPoint>& out) {
  point_shape_contact(x, surface_normal, SurfacePoint::at_node(node), node, shape, pose, margin, surface_is_a, planar,
                      out);
}

void surface_node_normals(const std::vector<Eigen::Vector3d>& positions, const DeformableSurfaceGeometry& geometry,
                          const std::vector<int>& nodes, std::vector<Eigen::Vector3d>& normals) {
  normals.resize(positions.size());
  for (int node : nodes) normals[node].setZero();
  for (const auto& [a, b] : geometry.segments) {  // (t_y, −t_x): outward, |t| long
    const Eigen::Vector3d t = positions[b] - positions[a];
    const Eigen::Vector3d n(t.y(), -t.x(), 0.0);
    normals[a] += n, normals[b] += n;
  }
  for (const auto& [a, b, c] : geometry.triangles) {  // twice the area, outward
    const Eigen::Vector3d n = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
    normals[a] += n, normals[b] += n, normals[c] += n;
  }
  for (int node : nodes)
    if (const double length = normals[node].norm(); length > 0.0) normals[node] /= length;
}

void curve_shape_contacts(const std::vector<Eigen::Vector3d>& positions, const DeformableSurfaceGeometry& geometry,
                          const Shape& shape, const Eigen::Isometry3d& pose, double margin, bool surface_is_a,
                          bool planar, int first_feature, std::vector<ContactPoint>& out) {
  for (int i = 0; i < static_cast<int>(geometry.curve.size()); ++i)
    for (int g = 0; g < kCurveGaussPoints; ++g) {
      const SurfacePoint point = curve_point(geometry.curve[i], kCurveGaussAbscissae[g]);
      // The curve runs in the boundary's outward order: its outward normal is (t_y, −t_x).
      const Eigen::Vector3d t = surface_position(curve_derivative(geometry.curve[i], kCurveGaussAbscissae[g]), positions);
      Eigen::Vector3d normal(t.y(), -t.x(), 0.0);
      if (const double length = normal.norm(); length > 0.0) normal /= length;
      point_shape_contact(surface_position(point, positions), normal, point, first_feature + kCurveGaussPoints * i + g,
                          shape, pose, margin, surface_is_a, planar, out);
    }
}

namespace {

// The closest point of the surface's faces to x: its distance (m), the point and its node weights,
// and whether x lies outside the body there.
struct FacePoint {
  double distance = std::numeric_limits<double>::infinity();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d face_normal = Eigen::Vector3d::UnitY();  // outward unit normal of the chosen face
  SurfacePoint weights;
  bool outside = false;
};

// Closest point of the triangle (a, b, c) to x as barycentric weights (Ericson, Real-Time Collision
// Detection, 2005, §5.1.5).
Eigen::Vector3d triangle_weights(const Eigen::Vector3d& x, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                 const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = x - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {1.0, 0.0, 0.0};
  const Eigen::Vector3d bp = x - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {0.0, 1.0, 0.0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return {1.0 - v, v, 0.0};
  }
  const Eigen::Vector3d cp = x - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {0.0, 0.0, 1.0};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return {1.0 - w, 0.0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0.0, 1.0 - w, w};
  }
  const double denominator = 1.0 / (va + vb + vc);
  const double v = vb * denominator, w = vc * denominator;
  return {1.0 - v - w, v, w};
}

FacePoint closest_face_point(const Eigen::Vector3d& x, const std::vector<Eigen::Vector3d>& positions,
                             const DeformableSurfaceGeometry& geometry, bool planar) {
  FacePoint best;
  // Near a corner of the surface the closest point is shared by several faces, and x is outside when
  // it is outside any of them: the side is the largest over the (near-)closest faces. Their normals
  // are summed: inside, a shape's vertex on a surface node takes the node's normal (as node features
  // do, surface_node_normals), not that of whichever face came first.
  double side = -std::numeric_limits<double>::infinity();
  Eigen::Vector3d tied_normals = Eigen::Vector3d::Zero();
  bool kinked = false;  // tied faces with different normals
  const auto consider = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& n, const SurfacePoint& w) {
    const double d = (x - p).norm();
    const double tie = best.weights.count == 0 ? 0.0 : 1e-12 * (1.0 + best.distance);
    if (best.weights.count == 0 || d < best.distance - tie) {
      best.distance = d, best.point = p, best.face_normal = n, best.weights = w;
      side = n.dot(x - p);
      tied_normals = n, kinked = false;
    } else if (d <= best.distance + tie) {
      side = std::max(side, n.dot(x - p));
      tied_normals += n, kinked = kinked || n != best.face_normal;
    }
  };
  if (planar) {
    for (const auto& [a, b] : geometry.segments) {
      const Eigen::Vector3d xa = positions[a], t = positions[b] - xa;
      const double length2 = t.squaredNorm();
      if (!(length2 > 0.0)) continue;
      const double s = std::clamp((x - xa).dot(t) / length2, 0.0, 1.0);
      const Eigen::Vector3d n = Eigen::Vector3d(t.y(), -t.x(), 0.0) / std::sqrt(length2);
      SurfacePoint w;
      w.count = 2, w.nodes = {a, b, 0}, w.weights = {1.0 - s, s, 0.0};
      consider(xa + s * t, n, w);
    }
  } else {
    for (const auto& [a, b, c] : geometry.triangles) {
      const Eigen::Vector3d normal = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
      if (!(normal.squaredNorm() > 0.0)) continue;
      const Eigen::Vector3d l = triangle_weights(x, positions[a], positions[b], positions[c]);
      SurfacePoint w;
      w.count = 3, w.nodes = {a, b, c}, w.weights = {l(0), l(1), l(2)};
      consider(l(0) * positions[a] + l(1) * positions[b] + l(2) * positions[c], normal.normalized(), w);
    }
  }
  best.outside = side > 0.0;
  if (kinked && tied_normals.norm() > 0.0) best.face_normal = tied_normals.normalized();
  return best;
}

}  // namespace

void shape_face_contacts(const std::vector<Eigen::Vector3d>& positions, const DeformableSurfaceGeometry& geometry,
                         const Shape& shape, const Eigen::Isometry3d& pose, double margin, bool surface_is_a,
                         bool planar, std::vector<ContactPoint>& out) {
  // The shape's features: (point, radius) — a sphere's centre with its radius, a box's vertices.
  std::array<Eigen::Vector3d, 8> features;
  int feature_count = 0;
  double radius = 0.0;
  if (const auto* sphere = std::get_if<Sphere>(&shape)) {
    features[feature_count++] = pose.translation();
    radius = sphere->radius;
  } else if (const auto* box = std::get_if<Box>(&shape)) {
    const Eigen::Vector3d& h = box->half_extents;
    for (int k = 0; k < (planar ? 4 : 8); ++k) {
      // Corners counter-clockwise in z, then the same above (the in-plane ones are the first four).
      const double sx = (k & 1) == (k >> 1 & 1) ? -1.0 : 1.0, sy = (k & 2) ? 1.0 : -1.0;
      const double sz = planar ? 0.0 : ((k & 4) ? 1.0 : -1.0);
      features[feature_count++] = pose * Eigen::Vector3d(sx * h.x(), sy * h.y(), sz * h.z());
    }
  } else if (std::holds_alternative<Halfspace>(shape)) {
    return;  // a halfspace has no point features
  } else {
    throw std::invalid_argument("face contact takes spheres, boxes and halfspaces, not a capsule, cylinder, "
                                "convex hull or mesh");
  }
  for (int k = feature_count - 1; k >= 0; --k) {  // features −1 − k ascending, as keys are sorted
    Eigen::Vector3d x = features[k];
    if (planar) x.z() = 0.0;
    const FacePoint f = closest_face_point(x, positions, geometry, planar);
    if (f.weights.count == 0) continue;
    // n: unit, from the surface towards the feature's body.
    Eigen::Vector3d n = f.face_normal;
    double distance = -f.distance;
    if (f.outside) {
      distance = f.distance;
      if (f.distance > 1e-12 * (1.0 + x.norm())) n = (x - f.point) / f.distance;
    }
    const double gap = distance - radius;
    if (gap > margin) continue;
    ContactPoint& c = out.emplace_back();
    c.key.feature = -1 - k;
    c.gap = gap;
    c.surface = f.weights;
    const Eigen::Vector3d on_shape = x - radius * n;
    if (surface_is_a) {
      c.point_a = f.point, c.point_b = on_shape, c.normal = n;
    } else {
      c.point_a = on_shape, c.point_b = f.point, c.normal = -n;
    }
    if (planar) c.point_a.z() = c.point_b.z() = c.normal.z() = 0.0;
  }
}

}  // namespace csim
