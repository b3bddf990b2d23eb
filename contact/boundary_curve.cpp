#include "contact/boundary_curve.h"

#include <cmath>
#include <map>

namespace csim {

namespace {

// Catmull–Rom basis (tension ½) in monomials of s: row j is the weight of control point P_j,
// x(s) = ½ [(−s + 2s² − s³) P0 + (2 − 5s² + 3s³) P1 + (s + 4s² − 3s³) P2 + (−s² + s³) P3].
Eigen::Matrix4d catmull_rom_basis() {
  Eigen::Matrix4d m;
  m << 0.0, -0.5, 1.0, -0.5,
       1.0, 0.0, -2.5, 1.5,
       0.0, 0.5, 2.0, -1.5,
       0.0, 0.0, -0.5, 0.5;
  return m;
}

// Adds `row` to node's coefficients, merging repeated nodes (a ghost control point lands on P1, P2).
void add_node(CurveSegment& segment, int node, const Eigen::RowVector4d& row) {
  for (int k = 0; k < segment.count; ++k)
    if (segment.nodes[k] == node) {
      segment.coefficients.row(k) += row;
      return;
    }
  segment.nodes[segment.count] = node;
  segment.coefficients.row(segment.count++) = row;
}

// True when the boundary turns by more than kCornerAngle at `middle` going from `before` to `after`.
bool is_corner(const Eigen::Vector3d& before, const Eigen::Vector3d& middle, const Eigen::Vector3d& after) {
  const Eigen::Vector3d incoming = middle - before, outgoing = after - middle;
  const double norms = incoming.norm() * outgoing.norm();
  return !(norms > 0.0) || incoming.dot(outgoing) < std::cos(kCornerAngle) * norms;
}

SurfacePoint weights_at(const CurveSegment& segment, const Eigen::Vector4d& monomials) {
  SurfacePoint point;
  point.count = segment.count;
  for (int k = 0; k < segment.count; ++k) {
    point.nodes[k] = segment.nodes[k];
    point.weights[k] = segment.coefficients.row(k).dot(monomials);
  }
  return point;
}

}  // namespace

std::vector<CurveSegment> catmull_rom_segments(const std::vector<std::array<int, 2>>& segments,
                                               const std::vector<Eigen::Vector3d>& reference_positions) {
  // Neighbours by shared node; a node where more than one segment starts (or ends) has no unique
  // neighbour and is treated as an end of chain.
  std::map<int, int> starting_at, ending_at;
  std::map<int, int> starts, ends;
  for (int i = 0; i < static_cast<int>(segments.size()); ++i) {
    starting_at[segments[i][0]] = i, ++starts[segments[i][0]];
    ending_at[segments[i][1]] = i, ++ends[segments[i][1]];
  }
  const Eigen::Matrix4d basis = catmull_rom_basis();
  std::vector<CurveSegment> curve;
  curve.reserve(segments.size());
  for (const auto& [a, b] : segments) {
    const Eigen::Vector3d &xa = reference_positions.at(a), &xb = reference_positions.at(b);
    int before = -1, after = -1;
    if (ends[a] == 1) before = segments[ending_at[a]][0];
    if (starts[b] == 1) after = segments[starting_at[b]][1];
    if (before >= 0 && is_corner(reference_positions.at(before), xa, xb)) before = -1;
    if (after >= 0 && is_corner(xa, xb, reference_positions.at(after))) after = -1;
    CurveSegment segment;
    add_node(segment, a, basis.row(1));
    add_node(segment, b, basis.row(2));
    // P0 = 2 P1 − P2 and P3 = 2 P2 − P1 where the neighbour is missing: linear extrapolation.
    if (before >= 0) add_node(segment, before, basis.row(0));
    else add_node(segment, a, 2.0 * basis.row(0)), add_node(segment, b, -basis.row(0));
    if (after >= 0) add_node(segment, after, basis.row(3));
    else add_node(segment, b, 2.0 * basis.row(3)), add_node(segment, a, -basis.row(3));
    curve.push_back(segment);
  }
  return curve;
}

std::vector<CurveSegment> quadratic_segments(const std::vector<std::array<int, 3>>& edges) {
  std::vector<CurveSegment> curve;
  curve.reserve(edges.size());
  for (const auto& [a, b, middle] : edges) {
    // The element's shape functions along the edge with ξ = 2s − 1: ξ(ξ − 1)/2, ξ(ξ + 1)/2, 1 − ξ².
    CurveSegment segment;
    add_node(segment, a, Eigen::RowVector4d(1.0, -3.0, 2.0, 0.0));
    add_node(segment, b, Eigen::RowVector4d(0.0, -1.0, 2.0, 0.0));
    add_node(segment, middle, Eigen::RowVector4d(0.0, 4.0, -4.0, 0.0));
    curve.push_back(segment);
  }
  return curve;
}

SurfacePoint curve_point(const CurveSegment& segment, double s) {
  return weights_at(segment, Eigen::Vector4d(1.0, s, s * s, s * s * s));
}

SurfacePoint curve_derivative(const CurveSegment& segment, double s) {
  return weights_at(segment, Eigen::Vector4d(0.0, 1.0, 2.0 * s, 3.0 * s * s));
}

Eigen::Vector3d surface_position(const SurfacePoint& point, const std::vector<Eigen::Vector3d>& positions) {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int k = 0; k < point.count; ++k) x += point.weights[k] * positions[point.nodes[k]];
  return x;
}

}  // namespace csim
