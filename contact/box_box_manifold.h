// Box–box contact manifold by face clipping, given the contact normal (lengths in m).
//
// FCL names the contact normal (its SAT, ODE's dBoxBox, when the boxes overlap or touch; GJK's witness
// points when they are apart); this file turns that normal into the points that hold a box at rest on
// another. FCL's own box–box manifold (dBoxBox with up to 4 points) is not used for that: it exists only
// for overlapping boxes (nothing within the margin before contact), its points are midpoints between the
// surfaces rather than material points, and they carry no identity from one step to the next (the warm
// start needs one).
//
// Method (Gregorius' reference/incident face clipping, as Box2D and Bullet do):
//   - reference face: the face of either box whose outward normal is along the contact normal (to
//     within kFaceAlignment); when both boxes have one (face on face), the larger face, the first box's
//     on a tie. No such face: an edge–edge contact, left to the single point of FCL;
//   - incident face: the other box's face most opposed to the reference normal;
//   - the incident face is clipped to the reference face in the reference face's plane; each vertex of
//     the clipped polygon whose gap (along the reference normal, from the reference face to the
//     incident face) is ≤ margin is a contact point; more than 4 are reduced to 4 (the deepest, then
//     those that span the largest area).
//   Plane scenes: the same on the boxes' z = 0 sections, faces are edges and at most 2 points remain.
//
// Features (ContactKey::feature), stable while the touching faces stay the same:
//   incident box vertex v (box_vertex numbering)                 v            (0..7)
//   reference box vertex v (a reference face corner)             8 + v        (8..15)
//   incident edge e (of incident face f) × reference face side s  16 + 16 f + 4 e + s   (16..111)
//   + 128 when the reference face is the second box's.
// A vertex of either box is a material point: its contact carries the arm on that box's side.
#pragma once

#include "contact/contact_point.h"
#include "contact/shape.h"

#include <Eigen/Geometry>
#include <vector>

namespace csim {

// Appends to `out` the manifold between boxes `first` and `second` at their poses, for the unit contact
// `normal` from first to second: normal, points (point_a on first), gap and feature set, frames left
// to the caller. Returns the number of points appended; 0 when no face of either box lies along
// `normal` (edge–edge) or no point has gap ≤ margin.
int box_box_face_manifold(const Box& first, const Eigen::Isometry3d& first_pose, const Box& second,
                          const Eigen::Isometry3d& second_pose, const Eigen::Vector3d& normal,
                          double margin, bool planar, std::vector<ContactPoint>& out);

}  // namespace csim
