// A smooth representation of a plane finite-element boundary, for contact at points between its nodes.
//
// Node-to-surface contact sees a coarse quad4 boundary as a polygon: a ring of 34 facets pressed on a
// flat ground touches it at 2–3 nodes and can balance a small friction torque by shifting normal force
// across a facet instead of turning (docs/rolling.md). Here the boundary is a curve that is linear in
// the nodal positions, x(s) = Σ_k w_k(s) x_k, so that a contact point at a fixed parameter s has the
// Jacobian row Σ_k w_k(s) on its nodes and a gap to a plane that is exactly linear in them:
// - quad4 boundaries (2-node segments): the uniform Catmull–Rom spline (Catmull & Rom 1974; the
//   Overhauser curve), C1, through the nodes; segment P1→P2 is a cubic in s ∈ [0, 1] of the four
//   consecutive nodes P0..P3. Where the chain ends, or turns by more than kCornerAngle at a node (a
//   corner of the body, not a facet of a curved boundary), the missing neighbour is the reflection
//   P0 = 2 P1 − P2, so a straight run of nodes stays straight up to its corner;
// - quad8 boundaries (3-node edges: corner, corner, mid-side): the element's own quadratic edge.
// Weights sum to 1 (a straight run of nodes maps to its line) but are not all ≥ 0 (a Catmull–Rom
// point is pulled by its outer neighbours with negative weights).
#pragma once

#include "contact/contact_point.h"

#include <Eigen/Core>
#include <array>
#include <vector>

namespace csim {

// Turn between consecutive boundary segments (rad, reference configuration) beyond which the node is a
// corner: a curved boundary meshed finely enough to be worth smoothing turns by much less (a 34-gon by
// 10.6°), the corners of blocks by 90°.
inline constexpr double kCornerAngle = 0.7853981633974483;  // 45°

// One segment of the curve: x(s) = Σ_k w_k(s) x(nodes[k]), s ∈ [0, 1] from its first end node to its
// second, with w_k(s) = Σ_p coefficients(k, p) s^p (dimensionless).
struct CurveSegment {
  int count = 0;  // nodes that move the segment: 2–4 (Catmull–Rom), 3 (quadratic edge)
  std::array<int, 4> nodes{};
  Eigen::Matrix4d coefficients = Eigen::Matrix4d::Zero();
};

// Catmull–Rom segments along the 2-node boundary segments (a, b) (outward order, each a→b; chains are
// found by shared nodes), with corners detected on the reference positions (m).
std::vector<CurveSegment> catmull_rom_segments(const std::vector<std::array<int, 2>>& segments,
                                               const std::vector<Eigen::Vector3d>& reference_positions);

// The quadratic edges (corner a, corner b, mid-side m), s = 0 at a and 1 at b.
std::vector<CurveSegment> quadratic_segments(const std::vector<std::array<int, 3>>& edges);

// The curve's point at s as node weights, and the weights of its derivative dx/ds (m per unit s).
SurfacePoint curve_point(const CurveSegment& segment, double s);
SurfacePoint curve_derivative(const CurveSegment& segment, double s);

// Σ_k w_k x(nodes[k]) (m) for the weights of a SurfacePoint.
Eigen::Vector3d surface_position(const SurfacePoint& point, const std::vector<Eigen::Vector3d>& positions);

// Gauss–Legendre points on [0, 1] per segment (contact points of the smoothed surface).
inline constexpr int kCurveGaussPoints = 3;
inline constexpr std::array<double, kCurveGaussPoints> kCurveGaussAbscissae = {
    0.1127016653792583, 0.5, 0.8872983346207417};  // (1 ∓ √(3/5)) / 2, ½

}  // namespace csim
