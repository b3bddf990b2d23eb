// A contact point between two collision objects, as returned by detection.
//
// Sign conventions (stated once, used everywhere):
//   normal  : unit, pointing from object A to object B;
//   gap     : signed distance along the normal, positive when open, negative when penetrating (m);
//   point_a, point_b : the closest (or deepest) points on A's and B's surfaces, world frame (m), with
//             point_b − point_a = gap·normal (exact for the analytic pairs);
//   (normal, t1, t2) : right-handed orthonormal frame; in plane scenes t1 lies in the plane z = 0 and
//             t2 = e_z is unused;
//   arm_a, arm_b : where point_a (point_b) is a material point of its shape (a box's vertex), the world
//             vector from the shape's origin to it, R times the point in the shape's frame (m); NaN
//             where the point is not a fixed point of the shape (a closest point, a node).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <compare>
#include <cstdint>
#include <limits>

namespace csim {

// Identity of a contact across steps (warm start, output, sorting): the two objects and the feature
// that touches (the box vertex index for box–halfspace, whichever of the two is A; 0 for pairs with
// one contact point; on a deformable surface, the node index ≥ 0 for its node features, −1 − k
// for feature k of the rigid shape landing on its faces, and node_count + G·segment + g for Gauss
// point g of a segment of its smoothed boundary, boundary_curve.h). object_a < object_b.
struct ContactKey {
  int object_a = -1;
  int object_b = -1;
  int feature = 0;
  auto operator<=>(const ContactKey&) const = default;
};

// The deformable side's point of a contact, as a combination of the surface's nodes:
// x = Σ weight[k] · x(nodes[k]), weights summing to 1 (a node feature: one node of weight 1;
// a point on a boundary segment or triangle: its linear interpolation weights, ≥ 0; a point of a
// smoothed boundary: its curve's weights on up to four nodes, some negative, boundary_curve.h).
struct SurfacePoint {
  int count = 0;  // 0 when neither object is a deformable surface
  std::array<int, 4> nodes{};
  std::array<double, 4> weights{};

  static SurfacePoint at_node(int node) {  // a node feature
    SurfacePoint point;
    point.count = 1;
    point.nodes[0] = node;
    point.weights[0] = 1.0;
    return point;
  }
};

struct ContactPoint {
  ContactKey key;
  SurfacePoint surface;
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d t1 = Eigen::Vector3d::UnitX();
  Eigen::Vector3d t2 = Eigen::Vector3d::UnitY();
  double gap = 0.0;
  // A rigid body's lever arm is taken from these where they are known, not as point − origin: the
  // position's rounding then does not reach the contact's rows, which stay the same to the bit while a
  // box slides without turning, and so does its Delassus operator (MoreauJean keeps it).
  Eigen::Vector3d arm_a = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::Vector3d arm_b = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  bool has_arm_a() const { return !std::isnan(arm_a.x()); }
  bool has_arm_b() const { return !std::isnan(arm_b.x()); }
};

// Completes (n, t1, t2). When `direction` has a component orthogonal to n, t1 is that component
// normalised (anisotropic friction axes are given this way); otherwise a deterministic choice.
// planar: t1 = e_z × n, t2 = e_z.
void complete_frame(ContactPoint& contact, bool planar,
                    const Eigen::Vector3d& direction = Eigen::Vector3d::Zero());

}  // namespace csim
