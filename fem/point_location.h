// A point of a mesh's reference configuration located in its elements, and the shape-function weights
// that interpolate a nodal field there: a probe of a field between the nodes (u(x) = Σ_a N_a(ξ) u_a).
//
// The element holding x is found by inverting its isoparametric map x(ξ) = Σ_a N_a(ξ) x_a (elements.h)
// with Newton's method from the element's centre ξ = 0 (Zienkiewicz & Taylor vol. 1, §9.3: the map is
// one to one where det J > 0), tried on the elements whose box holds x. quad4 and hexa8 lie in the
// box of their nodes (their N_a are ≥ 0 inside); a quad8's curved edges may bulge out of it, so its box
// is widened by a quarter of its diagonal.
#pragma once

#include "fem/elements.h"
#include "fem/mesh.h"

#include <Eigen/Core>
#include <array>
#include <optional>

namespace csim {

// A point of one element: its natural coordinates and the weights N_a(ξ) of the element's nodes.
struct MeshPoint {
  int element = -1;
  Eigen::Vector3d natural = Eigen::Vector3d::Zero();  // ξ ∈ [−1, 1]^d (components beyond d are 0)
  int count = 0;                                      // the element's node count
  std::array<int, kMaxElementNodes> nodes{};          // mesh node indices
  std::array<double, kMaxElementNodes> weights{};     // N_a(ξ), dimensionless, summing to 1
};

// Relative tolerance (of ξ's range 2) within which a point counts as inside an element: a point on a
// face or an edge is in the elements that share it.
inline constexpr double kLocationTolerance = 1e-9;

// The element that holds x (m, reference coordinates; z ignored for plane meshes) and the point's
// natural coordinates in it, or nullopt when no element does (|ξ_i| ≤ 1 + kLocationTolerance for all
// i; Newton's iteration is taken one step past a residual of 1e-12 of the element's size, to round-off).
// A point on a face shared by several elements is given in the one of lowest index (the field is
// continuous across it).
std::optional<MeshPoint> locate_point(const Mesh& mesh, const Eigen::Vector3d& x);

// Σ_a N_a values_a for a node-major field with d components a node (a mesh-wide dof vector:
// displacements, velocities); the components beyond d are 0.
Eigen::Vector3d interpolate(const Mesh& mesh, const MeshPoint& point, const Eigen::VectorXd& values);

}  // namespace csim
