// Clipping of an incident feature against a reference face (Gregorius' reference/incident clipping,
// as Box2D and Bullet's btPolyhedralContactClipping do). Internal to contact/; lengths in m.
//
// The reference is a convex polygon (3 or more points) or a segment (2 points: a plane scene's box face,
// a capsule's or cylinder's side, a box's or hull's edge), with the unit normal `normal` pointing out
// of it towards the incident shape. The incident feature is a convex polygon or a segment
// (support_features.h). The contact points are the vertices of the overlap of the two, projected
// along `normal`:
//   - each incident point over the reference (within its side planes, each through a reference edge
//     and `normal`; a reference segment's side planes are the planes across it at its ends);
//   - each reference point under the incident feature (inside an incident polygon, or between the ends
//     of an incident segment when the reference is a segment), moved along `normal` onto it;
//   - each crossing of an incident edge with a reference side plane, within the reference.
// Each has its gap: the height along `normal` of the incident point above the reference's plane
// (or line). Points whose gap exceeds the margin are dropped; points closer than 1e-9 × the features'
// size to an earlier one are one point (an incident vertex first, then a reference vertex, then a
// crossing); more than kMaxManifoldPoints are reduced to that many: the deepest, the farthest from it,
// then those spanning the largest triangle and quadrilateral (as Bullet's btPersistentManifold, since
// the support polygon is what keeps a body from tipping), each choice the first on ties to within
// 1e-9 so that symmetric cases (a cylinder's rim points over a face) keep the same points step after
// step.
//
// Feature numbers, from the features' ids (each < id_bound, the larger of the two shapes' bounds V):
//   incident point of id i                                  i
//   reference point of id j                                 V + j
//   incident edge from id i × reference side from id j       2 V + V i + j
// A point of the incident feature is a material point where its arm is set; so is a reference point.
#pragma once

#include "contact/support_features.h"

#include <Eigen/Geometry>
#include <vector>

namespace csim {

constexpr int kMaxManifoldPoints = 4;

struct ClippedPoint {
  Eigen::Vector3d reference_point;  // on the reference's plane or line (m)
  Eigen::Vector3d incident_point;   // = reference_point + gap · normal (m)
  double gap = 0.0;                 // m, positive when open
  int feature = 0;                  // numbering above
  Eigen::Vector3d reference_arm;    // NaN where not a material point
  Eigen::Vector3d incident_arm;
  Eigen::Vector2d in_plane;         // along the reference's in-plane axes (m), for the reduction
};

// Buffers reused from one call to the next (a query allocates nothing once they have grown).
struct ClipScratch {
  std::vector<Eigen::Vector2d> reference_2d, incident_2d;
  std::vector<double> heights;
  std::vector<ClippedPoint> kept;
};

// Sets `points` to the clipped points with gap ≤ margin, reduced to kMaxManifoldPoints.
void clip_features(const SupportFeature& reference, const Eigen::Vector3d& normal, const SupportFeature& incident,
                   double margin, int id_bound, ClipScratch& scratch, std::vector<ClippedPoint>& points);

}  // namespace csim
