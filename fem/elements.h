// Isoparametric elements for small-strain linear elasticity: quad4 (bilinear), quad8 (serendipity),
// hexa8 (trilinear), in the node order of mesh.h. Plane elements are plane strain with a thickness.
//
// Reference element: natural coordinates ξ = (ξ, η, ζ) ∈ [−1, 1]^d (ζ unused in 2D). Node a sits at
// ξ_a: quad4 and the corners of quad8 at (−1,−1), (1,−1), (1,1), (−1,1); the quad8 mid-side nodes
// at (0,−1), (1,0), (0,1), (−1,0); hexa8 at the quad4 corners with ζ = −1, then with ζ = +1.
//
// Formulas (Hughes, The Finite Element Method, 2000, ch. 3; Zienkiewicz & Taylor, The Finite
// Element Method vol. 1, 6th ed., ch. 6 and 9):
//   Jacobian        J_ij = ∂x_i/∂ξ_j = Σ_a x_ai ∂N_a/∂ξ_j,   ∂N_a/∂x = J⁻ᵀ ∂N_a/∂ξ
//   stiffness       K_e = ∫ Bᵀ D B dV,     consistent mass  M_e = ∫ ρ Nᵀ N dV,
//   with dV = t det J dξ dη (plane, thickness t) or det J dξ dη dζ, by full Gauss–Legendre
//   integration (2×2 for quad4, 3×3 for quad8, 2×2×2 for hexa8: exact for K and M of undistorted
//   elements).
// Strain and stress in Voigt order with engineering shears:
//   2D (plane strain): ε = (εxx, εyy, γxy), σzz = ν(σxx + σyy) (from εzz = 0);
//   3D:                ε = (εxx, εyy, εzz, γxy, γyz, γxz).
// Element dofs are node-major: node a of the element has dofs [d·a, d·a + d), d = 2 or 3.
// Every kernel checks det J > 0 at each Gauss point it uses and throws FemError
//   "element N has a non-positive Jacobian (inverted or degenerate)" otherwise.
#pragma once

#include "fem/material.h"
#include "fem/mesh.h"

#include <Eigen/Dense>
#include <vector>

namespace csim {

constexpr int kMaxElementNodes = 8;
constexpr int kMaxElementDofs = 24;

// Fixed-capacity (no heap) storage sized to the element at hand.
using NodeCoordinates =  // one row per node, x y z in m
    Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::ColMajor, kMaxElementNodes, 3>;
using ElementMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor,
                                    kMaxElementDofs, kMaxElementDofs>;
using ElementVector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxElementDofs, 1>;
// (σxx, σyy, σzz, σxy, σyz, σxz), Pa; tension positive.
using Stress = Eigen::Matrix<double, 6, 1>;

// ---- reference element --------------------------------------------------------------------------

struct ShapeFunctions {
  Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxElementNodes, 1>
      values;  // N_a, dimensionless
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kMaxElementNodes, 3>
      derivatives;  // row a: ∂N_a/∂ξ_j, j < dimension
};

// N and ∂N/∂ξ at the natural point ξ (components beyond the dimension ignored).
ShapeFunctions shape_functions(ElementType type, const Eigen::Vector3d& natural);

// The natural coordinates ξ_a of the nodes, in node order.
std::vector<Eigen::Vector3d> reference_nodes(ElementType type);

struct GaussPoint {
  Eigen::Vector3d natural = Eigen::Vector3d::Zero();  // ξ, components beyond the rule's dimension 0
  double weight = 0.0;
};

// Gauss–Legendre on [−1, 1] (in natural.x()), 1 ≤ points ≤ 4: exact for polynomials of degree
// 2·points − 1 (Hughes, table 3.8.1).
std::vector<GaussPoint> gauss_legendre(int points);

// The tensor-product rule of full integration: 2×2 (quad4), 3×3 (quad8), 2×2×2 (hexa8).
std::vector<GaussPoint> gauss_rule(ElementType type);

// ---- one element --------------------------------------------------------------------------------

// An element as the kernels see it. index is the element's index in its mesh, named in errors.
struct ElementGeometry {
  ElementType type = ElementType::quad4;
  NodeCoordinates coordinates;  // m, one row per node in the order of mesh.h
  int index = -1;
};

// The geometry of element e of the mesh. Throws FemError naming the element when e is out of range,
// its node count is not that of the mesh's type, or a node index is out of range.
ElementGeometry element_geometry(const Mesh& mesh, int element);

// The nodal values (node-major, d per node, as a mesh-wide dof vector: displacements, velocities) of
// element e's nodes, in the element's node order.
ElementVector element_values(const Mesh& mesh, int element, const Eigen::VectorXd& values);

// det J at each point of gauss_rule(type), in its order (m² in 2D, m³ in 3D); throws FemError (see
// above) at the first non-positive (or non-finite) value.
std::vector<double> jacobian_determinants(const ElementGeometry& element);

// K_e (N/m), n·d × n·d, symmetric. thickness (m) is used by plane elements only and must be > 0.
// The material must pass check_material (it is checked).
ElementMatrix element_stiffness(const ElementGeometry& element, const ElasticMaterial& material,
                                double thickness);

// Consistent mass M_e (kg), n·d × n·d: the scalar ∫ ρ N_a N_b dV on each direction.
ElementMatrix element_consistent_mass(const ElementGeometry& element, double density,
                                      double thickness);

// Diagonal lumped mass (kg per dof), n·d entries, each node's mass repeated on its d dofs.
//   quad4, hexa8: row sums of the consistent mass (positive for these elements);
//   quad8: HRZ scaling (Hinton, Rock & Zienkiewicz, Earthquake Eng. Struct. Dyn. 4, 1976, 245–249;
//          Zienkiewicz & Taylor vol. 1, §16.2.4): the row sums of a serendipity element are
//          negative at the corners (−1/12 of the element mass each on a rectangle), which would
//          make M indefinite, so the mass is instead m_a = M_aa · m_e / Σ_b M_bb, the consistent
//          diagonal scaled to the element mass m_e: positive, and the total is kept.
ElementVector element_lumped_mass(const ElementGeometry& element, double density, double thickness);

// Stress at the element centroid ξ = 0 (Pa) from the element's displacements (m, n·d entries, node-
// major). Plane strain: σzz = ν(σxx + σyy), σyz = σxz = 0.
Stress element_centroid_stress(const ElementGeometry& element, const ElasticMaterial& material,
                               const ElementVector& displacement);

// The centroid stresses of every element of a mesh (assembly.h's element_stresses, and the ParaView
// output's frame after frame): each element's ∂N/∂x at ξ = 0 is kept, so that a frame costs B u_e and
// Hooke's law an element, the same operations and hence the same bits as element_centroid_stress,
// without the element's geometry and Jacobian again. It keeps n·d numbers an element (8 a quad4, 16
// a quad8, 24 a hexa8).
class CentroidStressMap {
 public:
  // The mesh must outlive the map. Throws FemError as element_geometry and check_material do, or for
  // a non-positive det J at ξ = 0.
  CentroidStressMap(const Mesh& mesh, const ElasticMaterial& material);
  // σ at each element's centroid (Pa), in the mesh's element order, from the displacement of every
  // dof (m, node-major); throws FemError when its size is not the mesh's dof count.
  void stresses(const Eigen::VectorXd& displacement, std::vector<Stress>& out) const;

 private:
  const Mesh& mesh_;
  ElasticMaterial material_;
  std::vector<double> gradients_;  // each element's ∂N/∂x at ξ = 0, nodes × d, column-major
};

// ---- loads --------------------------------------------------------------------------------------

// Equivalent nodal forces (N) f_a = ∫ N_a (−p n) dA of a uniform pressure p (Pa) on one face:
// positive p pushes INTO the body, along −n, n the outward normal of mesh.h's Face convention.
//   quad4 mesh: 2-node edge, 2 Gauss points, times the thickness t (m);
//   quad8 mesh: 3-node edge (corner, corner, mid-side), 3 Gauss points, times t;
//   hexa8 mesh: 4-node quadrilateral face, 2×2 Gauss points (t unused).
// face_nodes holds the face's node coordinates in the face's order (2, 3 or 4 rows); the result has
// one block of d components per face node, in that order. element names the face's element in
// errors (a non-positive face Jacobian throws like an element's).
ElementVector face_pressure_forces(ElementType type, const NodeCoordinates& face_nodes,
                                   double pressure, double thickness, int element);

// Nodes of one face of the given element type: 2 (quad4), 3 (quad8), 4 (hexa8).
int nodes_per_face(ElementType type);

}  // namespace csim
