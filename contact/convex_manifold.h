// Contact manifolds of two convex shapes (box, cylinder, capsule, convex hull) by clipping their support
// features, given the contact normal FCL names (lengths in m). Internal to contact/.
//
// FCL names the normal and the deepest point (its SAT for box–box, GJK/EPA with the separation of
// gjk_pairs.h for the others) but gives one point, so a cylinder standing on a box would rock about it
// and a capsule lying on a box would rest on one point. FCL's own multi-point results are not used:
// dBoxBox's exists only for overlapping boxes, its points are midpoints rather than material points,
// and none carries an identity from step to step (the warm start needs one).
//
// Method (Bullet's btPolyhedralContactClipping, Gregorius' reference/incident clipping):
//   - reference: a face of either shape along the normal (support_features.h: a box's or hull's face,
//     a cylinder's cap), the larger one when both have one (the first shape's on a tie); its outward
//     normal is the contacts' normal. No such face: when both shapes offer a segment across the
//     normal (a capsule's core, a cylinder's side generator) and the two are parallel (to within
//     kAcrossAlignment), the longer segment, with FCL's normal made exactly across it; otherwise none;
//   - incident: the other shape's feature facing the reference (incident_feature);
//   - the incident feature clipped against the reference (feature_clipping.h): up to 4 points, each
//     with its gap along the reference normal, kept when ≤ margin.
// No reference, no incident feature, or fewer than `min_points` points: 0 is returned and the caller
// keeps FCL's single point (edge–edge, vertex–face, a tilted cylinder on its rim, round on round).
//
// Features (ContactKey::feature): clip_features' numbering with V the larger feature_id_bound of the two
// shapes, plus P when the reference is the second shape's, P the least power of two ≥ (V + 2) V.
// For two boxes (V = 8, P = 128): incident vertex v, reference vertex 8 + v, crossings 16 + 8 i + j.
#pragma once

#include "contact/contact_point.h"
#include "contact/feature_clipping.h"
#include "contact/shape.h"
#include "contact/support_features.h"

#include <Eigen/Geometry>
#include <vector>

namespace csim {

// Buffers reused from one query to the next (the narrow phase keeps one).
struct ManifoldScratch {
  SupportFeature on_first, on_second, reference, incident;
  ClipScratch clip;
  std::vector<ClippedPoint> points;
};

// Appends to `out` the manifold between `first` and `second` at their poses for the unit contact
// `normal` from first to second: normal, points (point_a on first), gap, feature and arms set, frames
// left to the caller. Returns the number of points appended: 0 (nothing appended) when the method
// above gives fewer than `min_points`.
int convex_manifold(const Shape& first, const Eigen::Isometry3d& first_pose, const Shape& second,
                    const Eigen::Isometry3d& second_pose, const Eigen::Vector3d& normal, double margin,
                    bool planar, int min_points, ManifoldScratch& scratch, std::vector<ContactPoint>& out);

}  // namespace csim
