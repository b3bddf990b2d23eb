// The support features of the convex shapes along a direction, for the face-clipping manifolds
// (contact/convex_manifold.h). Internal to contact/. Lengths in m, world frame.
//
// A feature is a convex polygon (3 or more points in cyclic order), a segment (2 points) or nothing
// (the shape touches at one point, which FCL's GJK already gives). Each point carries an id that
// stays the same from one step to the next while the same part of the shape touches (the warm
// start is keyed by it), and its arm (the world vector from the shape's origin) where it is a
// material point of the shape:
//   box       vertex v of box_vertex's numbering (narrow_phase.h), material, a face's corners and an
//             edge's ends alike; ids < 8;
//   cylinder  rim point j of rim k, kRimPoints·k + j (the numbering and points of cylinder–halfspace,
//             halfspace_pairs.h), material; the ends of a side generator 2·kRimPoints + k (not
//             material: the generator slides round the side as the cylinder rolls); ids < 2·kRimPoints + 2.
//             Why kRimPoints = 8 rather than 4: the same material points as on the floor, and a
//             polygon within r (1 − cos 22.5°) = 0.076 r of the true rim where the cap is clipped (a cap
//             as the reference, or one overhanging a face's edge) against 0.29 r for a square; the
//             clipping then keeps 4 of the points for the solver (feature_clipping.h), alternate ones
//             when the whole cap lies over a face.
//   capsule   the surface point over the core segment's end k (k = 0 at local z = −half_length), as
//             capsule–halfspace's features; not material (it rolls over the cap); ids < 2;
//   hull      its vertex index (among those make_convex kept), material, a face's corners and an
//             edge's ends alike; ids < vertex count.
// So a feature's ids stay the same while the same face, edge, rim or side touches, whatever the pose.
//
// Alignment: a face is along a direction d when 1 − n·d ≤ kFaceAlignment for its outward unit normal n
// (about 1.4e-3 rad: FCL's normal is a face normal exactly when it comes from a SAT, and within 1e-6
// rad of it from GJK, gjk_pairs.h); an axis is across d when |a·d| ≤ kAcrossAlignment, the sine of the
// same angle.
#pragma once

#include "contact/shape.h"

#include <Eigen/Geometry>
#include <vector>

namespace csim {

constexpr double kFaceAlignment = 1e-6;
constexpr double kAcrossAlignment = 1.4142135623730950e-3;  // sqrt(2 kFaceAlignment)

struct SupportFeature {
  std::vector<Eigen::Vector3d> points;  // world (m): a polygon's in cyclic order
  std::vector<Eigen::Vector3d> arms;    // world (m), from the shape's origin; NaN where not material
  std::vector<int> ids;
  // A polygon's (or a plane scene's face edge's) outward unit normal; unset for a shape's segment.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double size = 0.0;  // a polygon's area (m²), a segment's length (m): the larger feature is the reference

  int count() const { return static_cast<int>(points.size()); }
  void clear() { points.clear(), arms.clear(), ids.clear(), normal.setZero(), size = 0.0; }
};

// The face of the shape whose outward normal lies along `direction` (unit), within kFaceAlignment: a
// box's face (4 corners; in plane scenes the edge of its z = 0 section, 2 corners), a hull's face (its
// coplanar triangles merged into one polygon), a cylinder's cap (its kRimPoints rim points). False for
// spheres and capsules, and when no face is along `direction`.
bool face_along(const Shape& shape, const Eigen::Isometry3d& pose, const Eigen::Vector3d& direction, bool planar,
                SupportFeature& out);

// The feature that meets a reference face (or segment) whose outward normal is −direction: a box's or a
// hull's face most along `direction` (whatever its angle: the clipping keeps its points within the
// margin, as Bullet's btPolyhedralContactClipping does), a cylinder's cap when its axis is along
// `direction` and its side generator when across it, a capsule's core segment pushed out by its radius
// when across it. False where the shape touches at one point (a sphere, a tilted capsule or cylinder).
bool incident_feature(const Shape& shape, const Eigen::Isometry3d& pose, const Eigen::Vector3d& direction,
                      bool planar, SupportFeature& out);

// The segment of the shape across `direction` (unit) that reaches farthest along it, when the shape
// offers one: a capsule's core pushed out by its radius along `direction` and a cylinder's side
// generator, when their axis is across `direction`; a box's or a hull's edge whose direction e has
// |e·direction| ≤ kAcrossAlignment and that is the support along `direction` (a hull's: both its ends
// within kAcrossAlignment × its length of the support height). Meant where no face is along
// `direction` (face_along): a face's edge is then the support. False otherwise, for spheres, and for
// a box in a plane scene.
bool segment_across(const Shape& shape, const Eigen::Isometry3d& pose, const Eigen::Vector3d& direction,
                    bool planar, SupportFeature& out);

// One more than the largest id the shape's features carry.
int feature_id_bound(const Shape& shape);

}  // namespace csim
