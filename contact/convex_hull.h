// The convex hull of a point set, as the Convex shape (contact/shape.h) FCL's GJK takes, and the
// mass properties of a uniform solid hull.
//
// Why compute the faces rather than ask for them: a scene gives a hull by its points (a rock's
// scanned corners, a cube's eight vertices), and faces written by hand are easily inconsistent
// (inward, missing, not convex); FCL trusts them for its support search and volume. The hull is the
// incremental (beneath–beyond) construction (O'Rourke, Computational Geometry in C, 2nd ed., §4.3):
// a first tetrahedron, then each point in turn replaces the faces it sees by a fan from it to their
// horizon. O(n·F), for the tens to hundreds of points a collision hull has.
//
// A point within 1e-10 × the point set's extent of the hull (inside it, or on a face's plane) is
// not a vertex: faces of coplanar vertices come out as several triangles of one plane.
#pragma once

#include "contact/shape.h"

#include <Eigen/Dense>
#include <vector>

namespace csim {

// The hull of `points` (m): its vertices in the order given (interior points dropped), its
// triangles, counter-clockwise seen from outside, and its polygons and edges (shape.h). Throws std::invalid_argument with the reason for
// fewer than 4 points, a non-finite coordinate or points without volume (all on one plane).
Convex make_convex(const std::vector<Eigen::Vector3d>& points);

// Volume (m³), centroid (m) and inertia tensor about the centroid per unit density (m⁵) of the solid
// hull, from its faces by the divergence theorem (a tetrahedron from the first vertex to each face).
struct ConvexMassProperties {
  double volume = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia_per_density = Eigen::Matrix3d::Zero();
};
ConvexMassProperties convex_mass_properties(const Convex& convex);

}  // namespace csim
