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
//     normal (segment_across: a capsule's core, a cylinder's side generator, a box's or a hull's edge)
//     and the two are parallel (to within kAcrossAlignment), the longer segment, its normal the
//     common perpendicular of the two segments' lines (a capsule's or cylinder's axis, an edge) at the
//     middle of their overlap (exact where GJK's is 1e-6 to 1e-5 rad off; FCL's, made across the
//     segment, where the lines meet); otherwise none. So a box tilted onto an edge across a capsule's or a
//     cylinder's side, or along another box's parallel edge, touches along the segments' overlap;
//   - incident: the other shape's feature facing the reference (incident_feature), or its segment
//     across the normal when the reference is a segment;
//   - the incident feature clipped against the reference (feature_clipping.h): up to 4 points, each
//     with its gap along the reference normal, kept when ≤ margin.
// No reference, no incident feature, or fewer than `min_points` points: 0 is returned and the caller
// keeps FCL's single point (crossed edges, vertex–face, a tilted cylinder on its rim, round on round).
//
// Features (ContactKey::feature): clip_features' numbering with V the larger feature_id_bound of the two
// shapes, plus P when the reference is the second shape's, P the least power of two ≥ (V + 2) V.
// The ids are the shapes' own (support_features.h: a box's vertex, a hull's vertex, a cylinder's rim or
// generator end, a capsule's core end), and the reference is chosen by sizes that the pose does not
// change, so a contact keeps its number from step to step while the same features touch (the warm
// start's key). Examples:
//   two boxes (V = 8, P = 128): incident vertex v, reference vertex 8 + v, crossings 16 + 8 i + j;
//   a box's edge (ends v0, v1) on a capsule's side (the box first, V = 8, P = 128): the edge the longer,
//     the capsule's core ends k = 0, 1 as incident points (k) and the edge's ends (8 + v) as reference
//     points; the core the longer, 128 + v for the edge's ends and 128 + 8 + k for the core's ends;
//   a box's edge on a cylinder's side (V = 18, P = 512): the generator's ends are ids 16, 17 (k = 0, 1),
//     so 16 + k or 18 + v with the edge the reference, 512 + v or 512 + 18 + 16 + k with the generator.
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
