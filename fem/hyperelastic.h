// Isotropic hyperelastic laws for finite strain: a strain-energy density W(F) per unit reference
// volume (J/m³ = Pa), its first Piola–Kirchhoff stress and its tangent, all analytical.
//
// Conventions:
//   F = ∂x/∂X, the 3×3 deformation gradient (dimensionless), J = det F > 0; C = FᵀF, b = FFᵀ.
//   Plane strain is the 3D law at F33 = 1, F13 = F23 = F31 = F32 = 0: P33 is then the out-of-plane
//   stress that keeps the thickness fixed. The responses below take it as F's in-plane block F2 and
//   return P's and A's in-plane blocks, computed with 2×2 algebra (hyperelastic.cpp).
//   P = ∂W/∂F, first Piola–Kirchhoff stress, Pa (current force per reference area), tension
//   positive; the Cauchy stress is σ = J⁻¹ P Fᵀ.
//   A = ∂P/∂F = ∂²W/∂F∂F, Pa, a 9×9 matrix with A(3i + J, 3k + L) = ∂P_iJ/∂F_kL (F flattened row
//   by row); it is major-symmetric, A = Aᵀ.
//
// Laws (Holzapfel, Nonlinear Solid Mechanics, 2000, ch. 6; Bonet & Wood, Nonlinear Continuum
// Mechanics for Finite Element Analysis, 2nd ed. 2008, ch. 6; Abaqus Theory Guide, "Hyperelastic
// material behavior"):
//   saint_venant_kirchhoff  W = λ/2 (tr E)² + μ E:E,  E = ½(C − I); S = λ tr E I + 2μE, P = FS.
//                           Not polyconvex: it softens and loses stability in strong compression.
//   neo_hookean             W = μ/2 (I1 − 3) − μ ln J + λ/2 (ln J)²  (compressible, Bonet & Wood).
//   mooney_rivlin           W = C10 (Ī1 − 3) + C01 (Ī2 − 3) + K/2 (J − 1)², Ī1, Ī2 the invariants
//                           of C̄ = J^(−2/3) C (the Abaqus form with D1 = 2/K). The incompressible
//                           case (D1 = 0) is approached by a large K, e.g. 1e3 … 1e4 · μ0.
// All three linearize at F = I to Hooke's law with Lamé parameters (λ, μ); for Mooney–Rivlin
// μ = μ0 = 2(C10 + C01) and λ = K − 2μ0/3 (initial_moduli).
//
// Split W(F) = W_iso(F) + U(J), each part stress-free at F = I, so that an element may evaluate U
// at an element-mean J (mean dilatation, finite_strain.h) while W_iso stays at the Gauss point:
//   mooney_rivlin           W_iso = C10 (Ī1 − 3) + C01 (Ī2 − 3) (truly isochoric),
//                           U = K/2 (J − 1)²;
//   neo_hookean             W_iso = μ/2 (I1 − 3) − μ ln J (the μ part: not isochoric, but with a
//                           moderate bulk stiffness 2μ/3), U = λ/2 (ln J)² (the λ part, which locks);
//   saint_venant_kirchhoff  W_iso = W, U ≡ 0: (tr E)² is no function of J alone.
// Every evaluation throws FemError when det F ≤ 0 or is not finite (no law here has a meaning for
// an inverted material point).
#pragma once

#include "fem/mesh.h"

#include <Eigen/Dense>
#include <type_traits>

namespace csim {

enum class HyperelasticLaw { saint_venant_kirchhoff, neo_hookean, mooney_rivlin };
const char* to_string(HyperelasticLaw law);

// One law and its constants; only those of the law are read. Build with the factories below.
struct HyperelasticMaterial {
  HyperelasticLaw law = HyperelasticLaw::neo_hookean;
  double lambda = 0.0;   // Lamé's first parameter λ, Pa (saint_venant_kirchhoff, neo_hookean)
  double mu = 0.0;       // shear modulus μ, Pa (saint_venant_kirchhoff, neo_hookean)
  double c10 = 0.0;      // C10, Pa (mooney_rivlin)
  double c01 = 0.0;      // C01, Pa (mooney_rivlin)
  double bulk = 0.0;     // bulk modulus K, Pa (mooney_rivlin)
  double density = 0.0;  // ρ in the reference configuration, kg/m³
};

// From Young's modulus E (Pa) and Poisson's ratio ν (dimensionless) through the Lamé parameters of
// material.h. Throws FemError naming young, poisson or density (check_material's rules) otherwise.
HyperelasticMaterial saint_venant_kirchhoff(double young, double poisson, double density);
HyperelasticMaterial neo_hookean(double young, double poisson, double density);
// From C10, C01 and K (Pa). Checked by check_hyperelastic.
HyperelasticMaterial mooney_rivlin(double c10, double c01, double bulk, double density);

// Throws FemError "hyperelastic material: KEY = VALUE: RULE" unless the law's constants are finite
// and give a positive-definite linearization: saint_venant_kirchhoff, neo_hookean: mu > 0 and
// lambda > −2μ/3 (that is E > 0 and −1 < ν < 0.5); mooney_rivlin: c10 + c01 > 0 (key c10),
// bulk > 0; every law: density ≥ 0.
void check_hyperelastic(const HyperelasticMaterial& material);

// Lamé parameters (Pa) of the linearization at F = I.
struct InitialModuli {
  double lambda = 0.0;  // Pa
  double mu = 0.0;      // Pa
};
InitialModuli initial_moduli(const HyperelasticMaterial& material);

// A on the indices i, J, k, L < D, flattened with stride D (A(D i + J, D k + L)): D = 3 is the whole
// tangent; D = 2 its in-plane block, all that a plane-strain element needs (F33 = 1 is held).
template <int D>
using MaterialTangentOf = Eigen::Matrix<double, D * D, D * D>;  // Pa
using MaterialTangent = MaterialTangentOf<3>;

// W, P and (if asked) A of the whole law, or of its W_iso part, at F. D = 3: F, P and A whole.
// D = 2, plane strain: F is the in-plane block F2 of F = [[F2, 0], [0, 1]], P and A the in-plane
// blocks of the 3D law's (the same values up to round-off, at a fraction of the cost; P33 is left
// out: the 3D response at that F has it). The material is not checked (the callers check it once);
// with_tangent = false leaves tangent at zero.
template <int D>
struct HyperelasticResponseOf {
  double energy = 0.0;                                                       // W, J/m³
  Eigen::Matrix<double, D, D> stress = Eigen::Matrix<double, D, D>::Zero();  // P, Pa
  MaterialTangentOf<D> tangent = MaterialTangentOf<D>::Zero();               // A, Pa
};
using HyperelasticResponse = HyperelasticResponseOf<3>;
// F is not deduced (type_identity_t): D is 3 unless given, and F may be any expression.
template <int D = 3>
using GradientOf = std::type_identity_t<Eigen::Matrix<double, D, D>>;
template <int D = 3>
HyperelasticResponseOf<D> hyperelastic_response(const HyperelasticMaterial& material,
                                                const GradientOf<D>& F, bool with_tangent = true);
template <int D = 3>
HyperelasticResponseOf<D> isochoric_response(const HyperelasticMaterial& material,
                                             const GradientOf<D>& F, bool with_tangent = true);

// U(J) and its derivatives. U'(J) is the mean (hydrostatic) Cauchy stress of the volumetric part,
// tension positive: its share of σ is U'(J) I, of P is U'(J) J F⁻ᵀ.
struct VolumetricResponse {
  double energy = 0.0;       // U, J/m³
  double mean_stress = 0.0;  // U'(J), Pa
  double stiffness = 0.0;    // U''(J), Pa
};
VolumetricResponse volumetric_response(const HyperelasticMaterial& material, double J);

}  // namespace csim
