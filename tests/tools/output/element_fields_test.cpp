// The stress the output shows for an elastic body (tools/output/element_fields.h), on homogeneous
// motions of small meshes: a rigid motion of a finite-strain body is stress- and strain-free whatever
// the rotation (the linear law of the small strain was not: issue 29), and a uniaxial stretch and a
// simple shear give the Cauchy stress of each law in closed form, derived below from the strain
// energies of fem/hyperelastic.h (Holzapfel 2000, ch. 6), not from the code.
#include "tools/output/element_fields.h"

#include "fem/assembly.h"
#include "fem/mesh_generators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace csim {
namespace {

const HyperelasticMaterial kSaintVenantKirchhoff = saint_venant_kirchhoff(2e6, 0.3, 1000.0);
const HyperelasticMaterial kNeoHookean = neo_hookean(2e6, 0.3, 1000.0);
const HyperelasticMaterial kMooneyRivlin = mooney_rivlin(4e5, 1e5, 1e7, 1000.0);  // K = 10 μ0
const std::vector<HyperelasticMaterial> kLaws{kSaintVenantKirchhoff, kNeoHookean, kMooneyRivlin};

// Multi-element meshes away from the origin (u then differs from node to node under a rotation).
std::vector<Mesh> meshes() {
  const Placement placement{0.0, {1.0, 2.0, 0.0}};
  return {rectangle_mesh(2.0, 1.0, 3, 2, ElementType::quad4, placement),
          rectangle_mesh(2.0, 1.0, 3, 2, ElementType::quad8, placement),
          box_mesh(2.0, 1.0, 1.5, 2, 2, 2, {0.0, {1.0, 2.0, 3.0}})};
}

std::vector<FiniteStrainFormulation> formulations(ElementType type) {
  std::vector<FiniteStrainFormulation> out{FiniteStrainFormulation::standard,
                                           FiniteStrainFormulation::mean_dilatation};
  if (type == ElementType::quad8) out.push_back(FiniteStrainFormulation::linear_dilatation);
  return out;
}

// u = (F − I) X + c at every node, node-major; a plane mesh takes F's and c's in-plane part.
Eigen::VectorXd affine_displacement(const Mesh& mesh, const Eigen::Matrix3d& F, const Eigen::Vector3d& c) {
  const int d = mesh.dofs_per_node();
  Eigen::VectorXd u(mesh.dof_count());
  for (int i = 0; i < static_cast<int>(mesh.nodes.size()); ++i)
    u.segment(d * i, d) = ((F - Eigen::Matrix3d::Identity()) * mesh.nodes[i] + c).head(d);
  return u;
}

FeBody finite_strain_body(const Mesh& mesh, const HyperelasticMaterial& material,
                          FiniteStrainFormulation formulation) {
  return FeBody(mesh, FiniteStrainLaw{material, formulation}, 0.1, true, {});
}

std::string name(const Mesh& mesh, const HyperelasticMaterial& m, FiniteStrainFormulation f) {
  return std::string(to_string(mesh.element_type)) + " " + to_string(m.law) + " " + to_string(f);
}

Stress voigt(const Eigen::Matrix3d& s) {
  Stress v;
  v << s(0, 0), s(1, 1), s(2, 2), s(0, 1), s(1, 2), s(0, 2);
  return v;
}

// The largest modulus of a law (Pa): the scale of its round-off.
double modulus(const HyperelasticMaterial& m) {
  const InitialModuli moduli = initial_moduli(m);
  return moduli.lambda + 2.0 * moduli.mu;
}

TEST(ElementFields, RigidMotionOfAFiniteStrainBodyIsStressAndStrainFree) {
  for (const Mesh& mesh : meshes()) {
    const bool solid = mesh.dimension() == 3;
    for (double degrees : {90.0, 30.0}) {
      // 2D: about z; 3D: about an oblique axis, so that every component of F moves.
      const Eigen::Vector3d axis = solid ? Eigen::Vector3d(1.0, -2.0, 2.0).normalized() : Eigen::Vector3d::UnitZ();
      const Eigen::Matrix3d R = Eigen::AngleAxisd(degrees * M_PI / 180.0, axis).toRotationMatrix();
      const Eigen::VectorXd u = affine_displacement(mesh, R, {0.3, -0.7, solid ? 0.2 : 0.0});
      for (const HyperelasticMaterial& m : kLaws)
        for (FiniteStrainFormulation f : formulations(mesh.element_type)) {
          const ElementFields fields = element_fields(finite_strain_body(mesh, m, f), u);
          ASSERT_EQ(fields.stress.size(), mesh.elements.size());
          ASSERT_EQ(fields.strain.size(), mesh.elements.size());
          for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
            EXPECT_LT(fields.stress[e].cwiseAbs().maxCoeff(), 1e-13 * modulus(m))
                << name(mesh, m, f) << ", " << degrees << " degrees, element " << e;
            EXPECT_LT(fields.strain[e].cwiseAbs().maxCoeff(), 1e-14)
                << name(mesh, m, f) << ", " << degrees << " degrees, element " << e;
          }
        }
    }
  }
}

// ---- the closed forms --------------------------------------------------------------------------
// Uniaxial stretch F = diag(a, 1, 1) (J = a; in 2D the plane-strain stretch, F33 = 1) and simple
// shear F = I + γ e_x ⊗ e_y (J = 1, b = [[1 + γ², γ, 0], [γ, 1, 0], [0, 0, 1]]).

// Saint Venant–Kirchhoff: S = λ tr E I + 2μ E, σ = J⁻¹ F S Fᵀ.
//   stretch: E = diag((a² − 1)/2, 0, 0): σxx = a (λ + 2μ)(a² − 1)/2, σyy = σzz = λ (a² − 1)/(2a).
//   shear: E = [[0, γ/2, 0], [γ/2, γ²/2, 0], 0], tr E = γ²/2, S11 = S33 = λγ²/2, S22 = λγ²/2 + μγ²,
//   S12 = μγ; F S Fᵀ: σxx = S11 + 2γ S12 + γ² S22, σxy = S12 + γ S22, σyy = S22, σzz = S33.
Stress saint_venant_kirchhoff_stretch(const HyperelasticMaterial& m, double a) {
  Stress s = Stress::Zero();
  s(0) = a * (m.lambda + 2.0 * m.mu) * (a * a - 1.0) / 2.0;
  s(1) = s(2) = m.lambda * (a * a - 1.0) / (2.0 * a);
  return s;
}
Stress saint_venant_kirchhoff_shear(const HyperelasticMaterial& m, double g) {
  const double S11 = m.lambda * g * g / 2.0, S22 = S11 + m.mu * g * g, S12 = m.mu * g;
  Stress s = Stress::Zero();
  s << S11 + 2.0 * g * S12 + g * g * S22, S22, S11, S12 + g * S22, 0.0, 0.0;
  return s;
}

// neo-Hookean: W = μ/2 (I1 − 3) − μ ln J + λ/2 (ln J)² gives P = μ (F − F⁻ᵀ) + λ ln J F⁻ᵀ and
// σ = J⁻¹ P Fᵀ = [μ (b − I) + λ ln J I] / J.
//   stretch: σxx = [μ (a² − 1) + λ ln a] / a, σyy = σzz = λ ln a / a.
//   shear: σxx = μγ², σxy = μγ, σyy = σzz = 0.
Stress neo_hookean_stretch(const HyperelasticMaterial& m, double a) {
  Stress s = Stress::Zero();
  s(0) = (m.mu * (a * a - 1.0) + m.lambda * std::log(a)) / a;
  s(1) = s(2) = m.lambda * std::log(a) / a;
  return s;
}
Stress neo_hookean_shear(const HyperelasticMaterial& m, double g) {
  Stress s = Stress::Zero();
  s << m.mu * g * g, 0.0, 0.0, m.mu * g, 0.0, 0.0;
  return s;
}

// Mooney–Rivlin: W = C10 (Ī1 − 3) + C01 (Ī2 − 3) + K/2 (J − 1)² gives
// σ = (2/J) dev[(C10 + C01 Ī1) b̄ − C01 b̄²] + K (J − 1) I, b̄ = J^(−2/3) b: the deviator of the
// push-forward F̄ S̄ F̄ᵀ of S̄ = 2 ∂W_iso/∂C̄ = 2[(C10 + C01 Ī1) I − C01 C̄], over J, plus U'(J) I.
//   stretch: β = a^(−2/3), b̄ = β diag(a², 1, 1), Ī1 = β (a² + 2); with
//   D = (C10 + C01 Ī1) β (a² − 1) − C01 β² (a⁴ − 1) (the xx minus the yy entry of the bracket),
//   σxx = 4D/(3a) + K (a − 1), σyy = σzz = −2D/(3a) + K (a − 1).
//   shear (J = 1, Ī1 = 3 + γ²): σxy = 2 (C10 + C01) γ, σxx − σyy = 2 (C10 + C01) γ²,
//   σyy − σzz = −2 C01 γ², tr σ = 0, hence σxx = (4 C10 + 2 C01) γ²/3, σyy = −(2 C10 + 4 C01) γ²/3,
//   σzz = 2 (C01 − C10) γ²/3 (Rivlin's simple-shear results).
Stress mooney_rivlin_stretch(const HyperelasticMaterial& m, double a) {
  const double beta = std::pow(a, -2.0 / 3.0), I1 = beta * (a * a + 2.0);
  const double D = (m.c10 + m.c01 * I1) * beta * (a * a - 1.0) - m.c01 * beta * beta * (a * a * a * a - 1.0);
  Stress s = Stress::Zero();
  s(0) = 4.0 * D / (3.0 * a) + m.bulk * (a - 1.0);
  s(1) = s(2) = -2.0 * D / (3.0 * a) + m.bulk * (a - 1.0);
  return s;
}
Stress mooney_rivlin_shear(const HyperelasticMaterial& m, double g) {
  Stress s = Stress::Zero();
  s << (4.0 * m.c10 + 2.0 * m.c01) * g * g / 3.0, -(2.0 * m.c10 + 4.0 * m.c01) * g * g / 3.0,
      2.0 * (m.c01 - m.c10) * g * g / 3.0, 2.0 * (m.c10 + m.c01) * g, 0.0, 0.0;
  return s;
}

Stress closed_form_stretch(const HyperelasticMaterial& m, double a) {
  switch (m.law) {
    case HyperelasticLaw::saint_venant_kirchhoff: return saint_venant_kirchhoff_stretch(m, a);
    case HyperelasticLaw::neo_hookean: return neo_hookean_stretch(m, a);
    case HyperelasticLaw::mooney_rivlin: return mooney_rivlin_stretch(m, a);
  }
  throw std::logic_error("unknown law");
}
Stress closed_form_shear(const HyperelasticMaterial& m, double g) {
  switch (m.law) {
    case HyperelasticLaw::saint_venant_kirchhoff: return saint_venant_kirchhoff_shear(m, g);
    case HyperelasticLaw::neo_hookean: return neo_hookean_shear(m, g);
    case HyperelasticLaw::mooney_rivlin: return mooney_rivlin_shear(m, g);
  }
  throw std::logic_error("unknown law");
}

// σ as a matrix, to rotate it.
Eigen::Matrix3d tensor(const Stress& s) {
  Eigen::Matrix3d t;
  t << s(0), s(3), s(5), s(3), s(1), s(4), s(5), s(4), s(2);
  return t;
}

// Each motion on every mesh, law and formulation; then the same motion followed by a rotation Q,
// whose stress is Q σ Qᵀ (objectivity) and whose Green–Lagrange strain is unchanged.
void expect_closed_form(const char* motion, const Eigen::Matrix3d& F, Stress (*closed_form)(const HyperelasticMaterial&, double),
                        double amount) {
  for (const Mesh& mesh : meshes())
    for (double degrees : {0.0, 30.0}) {
      const Eigen::Matrix3d Q = Eigen::AngleAxisd(degrees * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      const Eigen::VectorXd u = affine_displacement(mesh, Q * F, {0.1, 0.2, mesh.dimension() == 3 ? 0.3 : 0.0});
      const Stress strain = voigt(0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity()));
      for (const HyperelasticMaterial& m : kLaws)
        for (FiniteStrainFormulation f : formulations(mesh.element_type)) {
          const Stress expected = voigt(Q * tensor(closed_form(m, amount)) * Q.transpose());
          const ElementFields fields = element_fields(finite_strain_body(mesh, m, f), u);
          for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
            EXPECT_LT((fields.stress[e] - expected).cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff())
                << motion << ", " << name(mesh, m, f) << ", rotated " << degrees << " degrees, element " << e
                << "\n  got      " << fields.stress[e].transpose() << "\n  expected " << expected.transpose();
            EXPECT_LT((fields.strain[e] - strain).cwiseAbs().maxCoeff(), 1e-13) << motion << ", " << name(mesh, m, f);
          }
        }
    }
}

TEST(ElementFields, UniaxialStretchGivesEachLawsCauchyStress) {
  const double a = 1.25;
  expect_closed_form("stretch", Eigen::Vector3d(a, 1.0, 1.0).asDiagonal().toDenseMatrix(), closed_form_stretch, a);
}

TEST(ElementFields, SimpleShearGivesEachLawsCauchyStress) {
  const double g = 0.4;
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(0, 1) = g;
  expect_closed_form("shear", F, closed_form_shear, g);
}

// A linear body keeps the small-strain stress of its linear law (fem/assembly.h), and has no strain
// field: the output of linear bodies is unchanged. The series of frames the ParaView output uses
// (its map formed at the first) gives the same, to the bit, frame after frame.
TEST(ElementFields, LinearBodyKeepsTheSmallStrainStress) {
  for (const Mesh& mesh : meshes()) {
    const ElasticMaterial steel{2e11, 0.3, 7800.0};
    const FeBody body(mesh, steel, 0.1, true, {});
    ElementFieldsSeries series(body);
    for (const double phase : {0.1, 0.6}) {
      Eigen::VectorXd u(mesh.dof_count());
      for (int r = 0; r < u.size(); ++r) u(r) = 1e-4 * std::sin(0.7 * r + phase);  // m
      const std::vector<Stress> linear = element_stresses(FeModel{mesh, steel, 0.1}, u);
      const ElementFields fields = element_fields(body, u), framed = series(u);
      ASSERT_EQ(fields.stress.size(), linear.size());
      ASSERT_EQ(framed.stress.size(), linear.size());
      for (std::size_t e = 0; e < linear.size(); ++e) {
        EXPECT_EQ(fields.stress[e], linear[e]);
        EXPECT_EQ(framed.stress[e], linear[e]);
      }
      EXPECT_TRUE(fields.strain.empty());
      EXPECT_TRUE(framed.strain.empty());
      EXPECT_EQ(framed.stress_description, fields.stress_description);
    }
  }
}

// A finite-strain body's series is element_fields itself.
TEST(ElementFields, FiniteStrainSeriesIsElementFields) {
  const Mesh mesh = meshes().front();
  const FeBody body = finite_strain_body(mesh, kNeoHookean, FiniteStrainFormulation::standard);
  Eigen::VectorXd u(mesh.dof_count());
  for (int r = 0; r < u.size(); ++r) u(r) = 1e-2 * std::sin(0.3 * r);  // m
  const ElementFields fields = element_fields(body, u), framed = ElementFieldsSeries(body)(u);
  ASSERT_EQ(framed.stress.size(), fields.stress.size());
  for (std::size_t e = 0; e < fields.stress.size(); ++e) {
    EXPECT_EQ(framed.stress[e], fields.stress[e]);
    EXPECT_EQ(framed.strain[e], fields.strain[e]);
  }
  EXPECT_EQ(framed.strain_description, fields.strain_description);
}

}  // namespace
}  // namespace csim
