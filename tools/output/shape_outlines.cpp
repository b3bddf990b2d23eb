#include "tools/output/shape_outlines.h"

#include <cmath>
#include <numbers>
#include <type_traits>
#include <variant>

namespace csim {

namespace {

template <typename>
constexpr bool kNoOutline = false;

// A unit vector orthogonal to the unit n, taken from the world axis least aligned with n (no
// cancellation), and the second tangent n × t1, so that (t1, t2, n) is right-handed.
std::pair<Eigen::Vector3d, Eigen::Vector3d> tangents(const Eigen::Vector3d& n) {
  Eigen::Index axis = 0;
  n.cwiseAbs().minCoeff(&axis);
  const Eigen::Vector3d t1 = n.cross(Eigen::Vector3d::Unit(axis)).normalized();
  return {t1, n.cross(t1)};
}

}  // namespace

ShapeOutline sphere_outline(const Sphere& sphere, const OutlineSettings& settings) {
  ShapeOutline out;
  const double r = sphere.radius;
  const double pi = std::numbers::pi;
  if (settings.dimension == 2) {
    std::vector<int> polygon;
    for (int k = 0; k < kDiskSides; ++k) {
      const double angle = 2.0 * pi * k / kDiskSides;
      out.points.emplace_back(r * std::cos(angle), r * std::sin(angle), 0.0);
      polygon.push_back(k);
    }
    out.polygons.push_back(polygon);
    return out;
  }
  // Poles 0 (−z) and 1 (+z), then the parallels from the south, kSphereSegments points each.
  out.points.emplace_back(0.0, 0.0, -r);
  out.points.emplace_back(0.0, 0.0, r);
  for (int ring = 1; ring < kSphereRings; ++ring) {
    const double polar = pi * ring / kSphereRings;  // from −z
    for (int k = 0; k < kSphereSegments; ++k) {
      const double azimuth = 2.0 * pi * k / kSphereSegments;
      out.points.emplace_back(r * std::sin(polar) * std::cos(azimuth), r * std::sin(polar) * std::sin(azimuth),
                              -r * std::cos(polar));
    }
  }
  const auto at = [](int ring, int k) { return 2 + (ring - 1) * kSphereSegments + k % kSphereSegments; };
  for (int k = 0; k < kSphereSegments; ++k) {
    out.polygons.push_back({0, at(1, k + 1), at(1, k)});  // seen from below: clockwise in azimuth
    for (int ring = 1; ring + 1 < kSphereRings; ++ring)
      out.polygons.push_back({at(ring, k), at(ring, k + 1), at(ring + 1, k + 1), at(ring + 1, k)});
    out.polygons.push_back({1, at(kSphereRings - 1, k), at(kSphereRings - 1, k + 1)});
  }
  return out;
}

ShapeOutline box_outline(const Box& box, const OutlineSettings& settings) {
  ShapeOutline out;
  const Eigen::Vector3d& h = box.half_extents;
  if (settings.dimension == 2) {
    out.points = {{-h.x(), -h.y(), 0.0}, {h.x(), -h.y(), 0.0}, {h.x(), h.y(), 0.0}, {-h.x(), h.y(), 0.0}};
    out.polygons = {{0, 1, 2, 3}};
    return out;
  }
  // Corner i has the sign of +x when bit 0 of i is set, of +y for bit 1, of +z for bit 2.
  for (int i = 0; i < 8; ++i)
    out.points.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
  out.polygons = {{0, 2, 3, 1},   // −z
                  {4, 5, 7, 6},   // +z
                  {0, 1, 5, 4},   // −y
                  {2, 6, 7, 3},   // +y
                  {0, 4, 6, 2},   // −x
                  {1, 3, 7, 5}};  // +x
  return out;
}

ShapeOutline halfspace_outline(const Halfspace& halfspace, const OutlineSettings& settings) {
  ShapeOutline out;
  const Eigen::Vector3d n = halfspace.normal.normalized();
  const Eigen::Vector3d centre = halfspace.offset * n;
  const double s = settings.halfspace_half_side;
  if (settings.dimension == 2) {
    const Eigen::Vector3d t(-n.y(), n.x(), 0.0);  // e_z × n
    out.points = {centre - s * t, centre + s * t};
    out.lines = {{0, 1}};
    return out;
  }
  const auto [t1, t2] = tangents(n);
  out.points = {centre - s * t1 - s * t2, centre + s * t1 - s * t2, centre + s * t1 + s * t2,
                centre - s * t1 + s * t2};
  out.polygons = {{0, 1, 2, 3}};
  return out;
}

ShapeOutline capsule_outline(const Capsule& capsule, const OutlineSettings&) {
  // The sphere's UV rings, the southern half moved down by the half length and the northern up, the
  // equator taken twice (the cylinder between): a closed surface of the capsule's points.
  ShapeOutline out;
  const double r = capsule.radius, l = capsule.half_length, pi = std::numbers::pi;
  out.points.emplace_back(0.0, 0.0, -r - l);
  out.points.emplace_back(0.0, 0.0, r + l);
  std::vector<std::pair<double, double>> rings;  // (polar angle from −z, z shift)
  for (int ring = 1; ring < kSphereRings; ++ring) {
    const double polar = pi * ring / kSphereRings;
    if (2 * ring <= kSphereRings) rings.emplace_back(polar, -l);
    if (2 * ring >= kSphereRings) rings.emplace_back(polar, l);
  }
  for (const auto& [polar, shift] : rings)
    for (int k = 0; k < kSphereSegments; ++k) {
      const double azimuth = 2.0 * pi * k / kSphereSegments;
      out.points.emplace_back(r * std::sin(polar) * std::cos(azimuth), r * std::sin(polar) * std::sin(azimuth),
                              -r * std::cos(polar) + shift);
    }
  const int count = static_cast<int>(rings.size());
  const auto at = [](int ring, int k) { return 2 + ring * kSphereSegments + k % kSphereSegments; };
  for (int k = 0; k < kSphereSegments; ++k) {
    out.polygons.push_back({0, at(0, k + 1), at(0, k)});
    for (int ring = 0; ring + 1 < count; ++ring)
      out.polygons.push_back({at(ring, k), at(ring, k + 1), at(ring + 1, k + 1), at(ring + 1, k)});
    out.polygons.push_back({1, at(count - 1, k), at(count - 1, k + 1)});
  }
  return out;
}

ShapeOutline cylinder_outline(const Cylinder& cylinder, const OutlineSettings&) {
  // kSphereSegments points on each rim (bottom first), the two caps and the side's quadrilaterals.
  ShapeOutline out;
  const double r = cylinder.radius, l = cylinder.half_length, pi = std::numbers::pi;
  for (const double z : {-l, l})
    for (int k = 0; k < kSphereSegments; ++k) {
      const double azimuth = 2.0 * pi * k / kSphereSegments;
      out.points.emplace_back(r * std::cos(azimuth), r * std::sin(azimuth), z);
    }
  std::vector<int> bottom, top;
  for (int k = 0; k < kSphereSegments; ++k) {
    bottom.push_back(kSphereSegments - 1 - k);  // clockwise seen from +z: counter-clockwise from below
    top.push_back(kSphereSegments + k);
    const int next = (k + 1) % kSphereSegments;
    out.polygons.push_back({k, next, kSphereSegments + next, kSphereSegments + k});
  }
  out.polygons.push_back(bottom);
  out.polygons.push_back(top);
  return out;
}

ShapeOutline convex_outline(const Convex& convex, const OutlineSettings&) {
  ShapeOutline out;
  out.points = convex.vertices;
  for (const auto& face : convex.faces) out.polygons.push_back({face[0], face[1], face[2]});
  return out;
}

ShapeOutline mesh_outline(const TriangleMesh& mesh, const OutlineSettings&) {
  ShapeOutline out;
  out.points = mesh.vertices;
  for (const auto& triangle : mesh.triangles) out.polygons.push_back({triangle[0], triangle[1], triangle[2]});
  return out;
}

ShapeOutline shape_outline(const Shape& shape, const OutlineSettings& settings) {
  return std::visit(
      [&settings](const auto& s) -> ShapeOutline {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Sphere>) return sphere_outline(s, settings);
        else if constexpr (std::is_same_v<T, Box>) return box_outline(s, settings);
        else if constexpr (std::is_same_v<T, Halfspace>) return halfspace_outline(s, settings);
        else if constexpr (std::is_same_v<T, Capsule>) return capsule_outline(s, settings);
        else if constexpr (std::is_same_v<T, Cylinder>) return cylinder_outline(s, settings);
        else if constexpr (std::is_same_v<T, Convex>) return convex_outline(s, settings);
        else if constexpr (std::is_same_v<T, TriangleMesh>) return mesh_outline(s, settings);
        else static_assert(kNoOutline<T>, "shape_outline: give this shape an outline function (shape_outlines.h)");
      },
      shape);
}

}  // namespace csim
