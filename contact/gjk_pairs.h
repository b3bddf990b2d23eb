// Pairs of convex shapes through FCL's GJK (libccd) and its penetration query: every pair of sphere,
// box, capsule, cylinder and convex hull but sphere–sphere, sphere–box and box–box (narrow_phase.cpp).
// Internal to contact/ (pair_query.h).
//
// Separated by kTouchingGap or more: GJK's distance and witness points (FCL's closed forms for
// sphere–capsule, sphere–cylinder and capsule–capsule), normal along the witness points, asked to a
// distance tolerance of 1e-12: FCL's default 1e-6 left a capsule beside a cylinder with a normal 6e-4
// rad off at a 1e-2 m gap (1e-6 rad with 1e-12).
//
// Closer, or overlapping: witness points of nearly touching shapes no longer fix the normal (a
// capsule lying on a box face: 2e-6 rad off at a 1e-10 m gap; at a gap of round-off the two points
// coincide), and at a gap of 0 FCL's GJK reports overlap while its penetration query (libccd's MPR,
// fcl::collide) may find none. So the second shape is translated away along u by s, to a gap of
// about kProbeGap, where GJK's distance d′ and normal n are good, and translated back: the gap is
// d′ − s (u·n) and the second shape's point moves back by −s u. Exact for flat faces and for u = n;
// otherwise the closest points slide by O(s·|u − n|²). Hence two separations: the first along a
// guess, the second along the n the first measured. The guesses, each until one separates the shapes
// within kMaxPulls doublings of s: when overlapping, MPR's normal (its depth added to s); when
// touching, the witness direction; then the line of centres (two faces in contact may give an MPR
// normal or a witness direction of round-off in their plane). One point per pair (feature 0).
#pragma once

#include "contact/pair_query.h"

namespace csim {

void gjk_pair(const CollisionShape& first, const CollisionShape& second, PairQuery& query,
              std::vector<ContactPoint>& out);

}  // namespace csim
