// Total-Lagrangian finite-strain elements for the hyperelastic laws of hyperelastic.h: quad4 and
// quad8 in plane strain (thickness t), hexa8 in 3D, in the node order of mesh.h. Rotations of any
// size are exact: the energy depends on u only through F.
//
// Kinematics: the mesh geometry is the reference configuration X (never updated); the current one
// is x = X + u; F = I + Σ_a u_a ⊗ ∂N_a/∂X at each Gauss point (plane strain: F33 = 1). Element
// dofs u_e are node-major (node a: [d·a, d·a + d)), mesh dofs as fem/assembly.h (node i:
// [d·i, d·i + d)), d = 2 or 3, in m.
//
// Each element is an energy Π_e(u_e) (J); its internal force f = ∂Π_e/∂u_e (N, the force the
// element exerts ON its nodes is −f; equilibrium is f = f_external) and tangent K_T = ∂f/∂u_e
// (N/m, symmetric) are its exact derivatives. Sign convention: fem/ returns this resisting force,
// the residual's sign (K u for a linear body); engine/ (Body::add_internal_force, Dynamics) adds the
// force ON the body, f_int = −∂Π/∂u = −K u, which FeBody obtains by subtracting fem's f. Both sides
// use the same positive K_T = ∂(fem's f)/∂u = −∂f_int/∂q. With B the map u_e → F (B_{iJ, bk} = δik ∂N_b/∂X_J)
// and dV = t det(∂X/∂ξ) w_g (plane) or det(∂X/∂ξ) w_g (solid), m³:
//   standard         Π_e = ∫ W(F) dV, full Gauss (2×2, 3×3, 2×2×2):
//                    f = ∫ Bᵀ P dV,   K_T = ∫ Bᵀ A B dV.
//   mean_dilatation  Π_e = ∫ W_iso(F) dV + V_e U(J̄),  J̄ = v_e / V_e, v_e = ∫ J dV, V_e = ∫ dV:
//                    f = ∫ Bᵀ P_iso dV + U'(J̄) g,   g = ∂v_e/∂u_e = ∫ Bᵀ J F⁻ᵀ dV,
//                    K_T = ∫ Bᵀ A_iso B dV + U''(J̄)/V_e g gᵀ + U'(J̄) ∫ Bᵀ (∂²J/∂F∂F) B dV,
//                    ∂²J/∂F∂F = J (F⁻ᵀ ⊗ F⁻ᵀ − F⁻ᵀ_iL F⁻ᵀ_kJ): in plane strain the constant
//                    pattern of the bilinear J = F11 F22 − F12 F21.
//   The element's volume change is one constant J̄, so the volumetric part (the one that locks when
//   K ≫ μ) constrains one mode per element: Q1/P0 for quad4 and hexa8, Q2/P0 for quad8 (Simo,
//   Taylor & Pister, CMAME 51, 1985, 177–208; Nagtegaal, Parks & Rice, CMAME 4, 1974, 153–177;
//   de Souza Neto, Perić & Owen, Computational Methods for Plasticity, 2008, ch. 15). With
//   saint_venant_kirchhoff (U ≡ 0) it is the standard element.
//   Q2/P0 leaves the linear variation of the volume change across an element free, which makes
//   coarse quad8 meshes too flexible in bending (nearly incompressible cantilever, L/H = 10, tip
//   deflection: +21 % with 2 elements through the depth, +3.6 % with 4, −0.1 % with 8, see
//   tests/fem/finite_strain_test.cpp); Q1/P0 converges from below without locking.
//   linear_dilatation  (quad8 only: Q2/P1, the pair of Abaqus' hybrid CPE8H) the same with J̄
//                    replaced by θ(X), the L² projection of J onto the linear functions on the
//                    element (3 modes; discontinuous between elements):
//                    Π_e = ∫ W_iso(F) dV + ∫ U(θ) dV, f and K_T as above with the pressure
//                    p(X) = the projection of U'(θ) in place of U'(J̄) (finite_strain.cpp). With
//                    U quadratic (Mooney–Rivlin) this is the Hu–Washizu element with a linear
//                    pressure and dilatation condensed per element (Simo, Taylor & Pister 1985).
//                    It constrains what Q2/P0 leaves free: the cantilever above converges from
//                    below to the 2D limit (≈ 0.985 of Timoshenko): −3.9 % with 1 element through
//                    the depth (Q2/P0: ×3.8, a spurious bending mode), −1.8 % with 2, −0.35 % with
//                    8. On quad4 and hexa8 it would lock: refused.
// Errors (FemError): an inverted or degenerate reference element ("element N has a non-positive
// Jacobian"), a current det F ≤ 0 at a Gauss point ("element N is inverted: det F = …"), a
// displacement of the wrong size, a thickness ≤ 0 for plane elements, a projected volume ratio θ ≤ 0
// ("element N is inverted: its projected volume ratio θ = …"), linear_dilatation on an element
// other than quad8, and the material's check_hyperelastic errors.
#pragma once

#include "fem/elements.h"
#include "fem/hyperelastic.h"
#include "fem/mesh.h"

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <vector>

namespace csim {

enum class FiniteStrainFormulation { standard, mean_dilatation, linear_dilatation };
const char* to_string(FiniteStrainFormulation formulation);

// Throws FemError when the element type cannot take the formulation: linear_dilatation needs quad8.
void check_formulation(ElementType type, FiniteStrainFormulation formulation);

// What an element evaluation computes: the tangent is the costly part, skipped in energy and
// force evaluations (line searches, explicit steps).
enum class FiniteStrainOutput { energy_and_force, energy_force_and_tangent };

struct FiniteStrainElementResult {
  double energy = 0.0;    // Π_e, J
  ElementVector force;    // f = ∂Π_e/∂u_e, N, n·d entries
  ElementMatrix tangent;  // K_T = ∂f/∂u_e, N/m, n·d × n·d; empty unless asked for
};

// One element at the displacement u_e (m, n·d entries, node-major). thickness (m) is read by
// plane elements only.
FiniteStrainElementResult finite_strain_element(
    const ElementGeometry& element, const HyperelasticMaterial& material, double thickness,
    FiniteStrainFormulation formulation, const ElementVector& displacement,
    FiniteStrainOutput output = FiniteStrainOutput::energy_force_and_tangent);

// Cauchy stress σ = J⁻¹ P Fᵀ at the element centroid ξ = 0 (Pa, Voigt order of elements.h's Stress,
// tension positive); mean_dilatation and linear_dilatation replace the volumetric part by p I, the
// element's (projected) pressure at the centroid. Plane strain: σzz is the stress that keeps F33 = 1.
Stress finite_strain_centroid_stress(const ElementGeometry& element,
                                     const HyperelasticMaterial& material,
                                     FiniteStrainFormulation formulation,
                                     const ElementVector& displacement);

// The deformation gradient F = ∂x/∂X at the element centroid ξ = 0 (dimensionless; plane strain
// F33 = 1, F13 = F23 = F31 = F32 = 0): the kinematics of finite_strain_centroid_stress, for strain
// measures such as the Green–Lagrange E = ½(FᵀF − I). Throws FemError as the element does (a
// non-positive reference Jacobian, det F ≤ 0, a displacement of the wrong size).
Eigen::Matrix3d finite_strain_centroid_gradient(const ElementGeometry& element,
                                                const ElementVector& displacement);

// ---- whole mesh ---------------------------------------------------------------------------------

// A mesh (not owned; it must outlive the model) of one element type and one material.
struct FiniteStrainModel {
  const Mesh& mesh;
  HyperelasticMaterial material;
  double thickness = 1.0;  // m, plane meshes only
  FiniteStrainFormulation formulation = FiniteStrainFormulation::standard;
};

// Π(u) = Σ_e Π_e, J, at the mesh displacement u (m, dof_count entries).
double strain_energy(const FiniteStrainModel& model, const Eigen::VectorXd& displacement);

// Internal force f = ∂Π/∂u (N, resized to dof_count, summed over elements). Returns Π (J).
double internal_force(const FiniteStrainModel& model, const Eigen::VectorXd& displacement,
                      Eigen::VectorXd& force);

// The tangent K_T = ∂f/∂u (N/m) as triplets, one per entry of every element matrix (duplicates to
// be summed by setFromTriplets), in element order. The list is cleared first and keeps its
// capacity, so that a caller reusing it across Newton iterations does not allocate.
void tangent_triplets(const FiniteStrainModel& model, const Eigen::VectorXd& displacement,
                      std::vector<Eigen::Triplet<double>>& triplets);

// The three in one pass over the elements, as a Newton iteration needs them. Returns Π (J).
double assemble_finite_strain(const FiniteStrainModel& model, const Eigen::VectorXd& displacement,
                              Eigen::VectorXd& force,
                              std::vector<Eigen::Triplet<double>>& triplets);

// The same with the tangent's rows and columns renumbered on the way, for a caller whose unknowns
// are some of the mesh dofs: mesh dof i becomes offset + numbering[i], and an entry whose row or
// column has numbering −1 (a fixed dof) is left out; appended to triplets, in the same order. The
// force stays over the mesh dofs.
struct DofNumbering {
  const std::vector<int>& numbering;  // per mesh dof
  int offset = 0;
};
double assemble_finite_strain(const FiniteStrainModel& model, const Eigen::VectorXd& displacement,
                              Eigen::VectorXd& force, const DofNumbering& numbering,
                              std::vector<Eigen::Triplet<double>>& triplets);

// finite_strain_centroid_stress of every element, in element order.
std::vector<Stress> cauchy_stresses(const FiniteStrainModel& model,
                                    const Eigen::VectorXd& displacement);

// finite_strain_centroid_gradient of every element of the mesh, in element order (u: m, dof_count
// entries).
std::vector<Eigen::Matrix3d> centroid_gradients(const Mesh& mesh, const Eigen::VectorXd& displacement);

}  // namespace csim
