#include "contact/deformable_surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace csim {

namespace {

// Signed distance of x to the shape (m, positive outside), the closest surface point, and the
// shape's outward unit normal there.
struct Projection {
  double distance;
  Eigen::Vector3d point, normal;
};

Projection project(const Eigen::Vector3d& x, const Shape& shape, const Eigen::Isometry3d& pose, bool planar) {
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
  // Box: outside, the clamped point; inside, the nearest face.
  const Box& box = std::get<Box>(shape);
  Eigen::Vector3d local = pose.inverse() * x;
  Eigen::Vector3d h = box.half_extents;
  if (planar) h.z() = std::numeric_limits<double>::infinity(), local.z() = 0.0;
  const Eigen::Vector3d clamped = local.cwiseMax(-h).cwiseMin(h);
  if ((clamped - local).squaredNorm() > 0.0) {
    const Eigen::Vector3d n = (local - clamped).normalized();
    return {(local - clamped).norm(), pose * clamped, pose.linear() * n};
  }
  int axis = 0;
  double depth = std::numeric_limits<double>::infinity();
  for (int i = 0; i < (planar ? 2 : 3); ++i) {
    const double to_face = h(i) - std::abs(local(i));
    if (to_face < depth) depth = to_face, axis = i;
  }
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  n(axis) = local(axis) >= 0.0 ? 1.0 : -1.0;
  Eigen::Vector3d on_face = local;
  on_face(axis) = n(axis) * h(axis);
  return {-depth, pose * on_face, pose.linear() * n};
}

}  // namespace

namespace {

// A contact of the surface point x (its node weights `surface`) with the shape, if gap ≤ margin.
void point_shape_contact(const Eigen::Vector3d& x, const SurfacePoint& surface, int feature, const Shape& shape,
                         const Eigen::Isometry3d& pose, double margin, bool surface_is_a, bool planar,
                         std::vector<ContactPoint>& out) {
  const Projection p = project(x, shape, pose, planar);
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

void node_shape_contact(const Eigen::Vector3d& x, int node, const Shape& shape, const Eigen::Isometry3d& pose,
                        double margin, bool surface_is_a, bool planar, std::vector<ContactPoint>& out) {
  point_shape_contact(x, SurfacePoint::at_node(node), node, shape, pose, margin, surface_is_a, planar, out);
}

void curve_shape_contacts(const std::vector<Eigen::Vector3d>& positions, const DeformableSurfaceGeometry& geometry,
                          const Shape& shape, const Eigen::Isometry3d& pose, double margin, bool surface_is_a,
                          bool planar, int first_feature, std::vector<ContactPoint>& out) {
  for (int i = 0; i < static_cast<int>(geometry.curve.size()); ++i)
    for (int g = 0; g < kCurveGaussPoints; ++g) {
      const SurfacePoint point = curve_point(geometry.curve[i], kCurveGaussAbscissae[g]);
      point_shape_contact(surface_position(point, positions), point, first_feature + kCurveGaussPoints * i + g,
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
  // Near a convex corner of the surface the closest point is shared by several faces, and x is
  // outside when it is outside any of them: the side is the largest over the (near-)closest faces.
  double side = -std::numeric_limits<double>::infinity();
  const auto consider = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& n, const SurfacePoint& w) {
    const double d = (x - p).norm();
    const double tie = best.weights.count == 0 ? 0.0 : 1e-12 * (1.0 + best.distance);
    if (best.weights.count == 0 || d < best.distance - tie) {
      best.distance = d, best.point = p, best.face_normal = n, best.weights = w;
      side = n.dot(x - p);
    } else if (d <= best.distance + tie) {
      side = std::max(side, n.dot(x - p));
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
  } else {
    return;  // a halfspace has no point features
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
