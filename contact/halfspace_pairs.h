// Closed-form manifolds of the rounded and hull shapes against a halfspace (internal to contact/,
// pair_query.h). FCL's capsule–, cylinder– and convex–halfspace queries give one penetrating point
// and nothing when separated; a body resting on the ground needs every point within the margin, each
// with its exact gap.
//
// capsule–halfspace   its two end-cap spheres, each as sphere–halfspace: feature 0 the cap about
//                     (0, 0, −h), 1 the cap about (0, 0, +h) (shape frame). A capsule lying on the
//                     ground rests on both; no lever arm (the point rolls over the cap).
// cylinder–halfspace  features 0..15: kRimPoints points of each rim, material points with their arm
//                     (rim k at z = (2k − 1)·h, point j at angle 2πj/kRimPoints from local x: feature
//                     kRimPoints·k + j), so that a cylinder standing on a face rests on a polygon of
//                     them; features 16 and 17: the exact lowest point of rim 0 and rim 1 (not
//                     material: it slides round the rim as the cylinder rolls), so that a cylinder on
//                     its side rests on its true generator and a tilted one on its true edge point.
//                     The rim points only while the axis is within 45° of the normal (|a·n| ≥
//                     kFaceDown): a rim point passing under a cylinder that rolls on its side is open
//                     but closing, and Moreau–Jean's activation by predicted gap would hold it,
//                     braking the roll (measured: a cylinder rolling down a 20° incline lost 1.5e-4 of
//                     its travel in 0.5 s). The lowest points are left out when the axis is within
//                     kUprightTilt of the normal, where every rim point is as low and the polygon
//                     carries the cylinder.
// convex–halfspace    every vertex whose gap ≤ margin (feature = vertex index), a material point with
//                     its arm, as box–halfspace.
#pragma once

#include "contact/pair_query.h"

namespace csim {

constexpr int kRimPoints = 8;
constexpr double kUprightTilt = 1e-9;           // rad
constexpr double kFaceDown = 0.70710678118654752;  // cos 45°

void capsule_halfspace(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
                       std::vector<ContactPoint>& out);
void cylinder_halfspace(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
                        std::vector<ContactPoint>& out);
void convex_halfspace(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
                      std::vector<ContactPoint>& out);

// Rim point j of rim k (numbering above) in the cylinder's frame (m).
Eigen::Vector3d cylinder_rim_point(const Cylinder& cylinder, int rim, int j);

}  // namespace csim
