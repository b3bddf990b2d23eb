// Finite-strain elements of fem/finite_strain.h: exact derivatives (central differences), exact
// large rotations, the large-strain patch test, the small-strain limit (fem's linear elements),
// errors, and volumetric locking of a nearly incompressible cantilever against beam theory.
//
// Tolerances. Element sizes are about 1 m and displacements 0.1 m, so central differences with
// h = 1e-6 m carry a truncation error ~ h² ≈ 1e-12 and a round-off error ~ ε Π / h ≈ 1e-10
// relative: 1e-6 fails for any wrong term. Rigid motions and homogeneous deformations are exact in
// these elements (F is then exactly constant), so they are checked to 1e-10 relative, round-off
// only. The small-strain comparison at |u| ~ 1e-8 m differs by O(|u|/L) ≈ 1e-7 from the linear
// element (and by a round-off ε/1e-8 ≈ 1e-8 from the cancellation in F − F⁻ᵀ), checked to 1e-6.
#include "fem/finite_strain.h"

#include "fem/assembly.h"
#include "tests/fem/test_meshes.h"

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

namespace csim {
namespace {

const ElementType kTypes[] = {ElementType::quad4, ElementType::quad8, ElementType::hexa8};
// The formulations an element type takes: linear_dilatation (Q2/P1) is quad8's only.
std::vector<FiniteStrainFormulation> formulations(ElementType type) {
  std::vector<FiniteStrainFormulation> list = {FiniteStrainFormulation::standard,
                                               FiniteStrainFormulation::mean_dilatation};
  if (type == ElementType::quad8) list.push_back(FiniteStrainFormulation::linear_dilatation);
  return list;
}
const HyperelasticMaterial kSvk = saint_venant_kirchhoff(2.0e6, 0.3, 1000.0);
const HyperelasticMaterial kNeoHookean = neo_hookean(2.0e6, 0.45, 1000.0);
const HyperelasticMaterial kMooneyRivlin =
    mooney_rivlin(0.4e6, 0.1e6, 1.0e8, 1100.0);  // K = 100 μ0
const HyperelasticMaterial kMaterials[] = {kSvk, kNeoHookean, kMooneyRivlin};
constexpr double kThickness = 0.2;  // m

int dimension_of(ElementType type) { return type == ElementType::hexa8 ? 3 : 2; }

std::string name(ElementType type, FiniteStrainFormulation formulation,
                 const HyperelasticMaterial& material) {
  return std::string(to_string(type)) + " " + to_string(formulation) + " " +
         to_string(material.law);
}

// One element of 2 × 1 (× 0.5) m, optionally with every node moved by up to 0.15 m.
ElementGeometry single_element(ElementType type, bool distorted) {
  Mesh mesh = type == ElementType::hexa8 ? test::box(1, 1, 1, 2.0, 1.0, 0.5)
                                         : test::rectangle(type, 1, 1, 2.0, 1.0);
  if (distorted) test::distort(mesh, 0.15);
  return element_geometry(mesh, 0);
}

// A rotation by 35° (about z, or about a skew axis in 3D) of a stretch with shear, det ≈ 1.05.
Eigen::Matrix3d moderate_gradient(int dimension) {
  Eigen::Matrix3d stretch;
  if (dimension == 2)
    stretch << 1.15, 0.10, 0.0, 0.05, 0.92, 0.0, 0.0, 0.0, 1.0;
  else
    stretch << 1.15, 0.10, 0.05, 0.05, 0.92, -0.04, 0.02, 0.03, 1.08;
  const Eigen::Vector3d axis =
      dimension == 2 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d(0.2, -0.4, 0.9).normalized();
  return Eigen::AngleAxisd(35.0 * M_PI / 180.0, axis).toRotationMatrix() * stretch;
}

// u_a = (F − I) X_a + c, node-major.
ElementVector affine_displacement(const NodeCoordinates& X, const Eigen::Matrix3d& F,
                                  const Eigen::Vector3d& translation, int dimension) {
  ElementVector u(X.rows() * dimension);
  for (int a = 0; a < X.rows(); ++a)
    u.segment(dimension * a, dimension) =
        ((F - Eigen::Matrix3d::Identity()) * X.row(a).transpose() + translation).head(dimension);
  return u;
}

// The moderate homogeneous deformation plus a non-homogeneous part of up to 0.04 m per dof.
ElementVector moderate_displacement(const ElementGeometry& element) {
  const int d = dimension_of(element.type);
  ElementVector u =
      affine_displacement(element.coordinates, moderate_gradient(d), Eigen::Vector3d::Zero(), d);
  for (int r = 0; r < u.size(); ++r) u(r) += 0.04 * std::sin(2.1 * r + 0.4);
  return u;
}

TEST(FiniteStrainElement, ForceAndTangentMatchCentralDifferences) {
  const double h = 1e-6;  // m
  for (ElementType type : kTypes) {
    const ElementGeometry element = single_element(type, true);
    const ElementVector u = moderate_displacement(element);
    for (FiniteStrainFormulation formulation : formulations(type)) {
      double worst_force = 0.0, worst_tangent = 0.0;
      for (const HyperelasticMaterial& m : kMaterials) {
        auto at = [&](const ElementVector& v) {
          return finite_strain_element(element, m, kThickness, formulation, v);
        };
        const FiniteStrainElementResult r = at(u);
        const int n = static_cast<int>(u.size());
        ElementVector force_fd(n);
        ElementMatrix tangent_fd(n, n);
        for (int c = 0; c < n; ++c) {
          ElementVector plus = u, minus = u;
          plus(c) += h, minus(c) -= h;
          const FiniteStrainElementResult rp = at(plus), rm = at(minus);
          force_fd(c) = (rp.energy - rm.energy) / (2 * h);
          tangent_fd.col(c) = (rp.force - rm.force) / (2 * h);
        }
        const double force_error =
            (force_fd - r.force).cwiseAbs().maxCoeff() / r.force.cwiseAbs().maxCoeff();
        const double tangent_error =
            (tangent_fd - r.tangent).cwiseAbs().maxCoeff() / r.tangent.cwiseAbs().maxCoeff();
        EXPECT_LT(force_error, 1e-6) << name(type, formulation, m);
        EXPECT_LT(tangent_error, 1e-6) << name(type, formulation, m);
        EXPECT_EQ((r.tangent - r.tangent.transpose()).cwiseAbs().maxCoeff(), 0.0);
        // Energy-and-force evaluations agree with the full one.
        const FiniteStrainElementResult light = finite_strain_element(
            element, m, kThickness, formulation, u, FiniteStrainOutput::energy_and_force);
        EXPECT_EQ(light.energy, r.energy);
        EXPECT_EQ((light.force - r.force).cwiseAbs().maxCoeff(), 0.0);
        EXPECT_EQ(light.tangent.size(), 0);
        worst_force = std::max(worst_force, force_error);
        worst_tangent = std::max(worst_tangent, tangent_error);
      }
      std::printf("[ measured ] %-6s %-16s FD relative error: force %.2e, tangent %.2e\n",
                  to_string(type), to_string(formulation), worst_force, worst_tangent);
    }
  }
}

TEST(FiniteStrainElement, RigidRotationOfNinetyDegreesIsStrainFree) {
  for (ElementType type : kTypes) {
    const int d = dimension_of(type);
    const ElementGeometry element = single_element(type, true);
    Eigen::Matrix3d R = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    if (d == 3) R = R * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
    const ElementVector u = affine_displacement(element.coordinates, R, {0.3, -0.7, 0.2}, d);
    const double volume = d == 2 ? 2.0 * kThickness : 1.0;  // m³, about
    for (FiniteStrainFormulation formulation : formulations(type))
      for (const HyperelasticMaterial& m : kMaterials) {
        const double mu = initial_moduli(m).mu;
        // A nodal force of a unit strain: μ times a face area (1 m × t, or 1 m²).
        const double force_scale = mu * (d == 2 ? kThickness : 1.0);
        const FiniteStrainElementResult r =
            finite_strain_element(element, m, kThickness, formulation, u);
        EXPECT_LT(std::abs(r.energy), 1e-10 * mu * volume) << name(type, formulation, m);
        EXPECT_LT(r.force.cwiseAbs().maxCoeff(), 1e-10 * force_scale) << name(type, formulation, m);
        const Stress sigma = finite_strain_centroid_stress(element, m, formulation, u);
        EXPECT_LT(sigma.cwiseAbs().maxCoeff(), 1e-10 * mu) << name(type, formulation, m);
      }
  }
}

// A homogeneous deformation u = (F0 − I) X + c of a patch of distorted elements is reproduced
// exactly: F = F0 at every centroid, no force on interior nodes, energy W(F0) V, Cauchy stress
// J⁻¹ P(F0) F0ᵀ everywhere.
void patch_test(Mesh mesh, double amplitude) {
  test::distort(mesh, amplitude, /*interior_only=*/true);
  const int d = mesh.dimension();
  const double volume = d == 2 ? 3.0 * 2.0 * kThickness : 1.0;  // m³
  const Eigen::Matrix3d F0 = moderate_gradient(d);
  Eigen::VectorXd u(mesh.dof_count());
  for (int i = 0; i < static_cast<int>(mesh.nodes.size()); ++i)
    u.segment(d * i, d) =
        ((F0 - Eigen::Matrix3d::Identity()) * mesh.nodes[i] + Eigen::Vector3d(0.1, 0.2, 0.3))
            .head(d);
  const std::vector<int>& boundary = mesh.node_sets["boundary"];
  for (const Eigen::Matrix3d& F : centroid_gradients(mesh, u))
    EXPECT_LT((F - F0).cwiseAbs().maxCoeff(), 1e-12) << to_string(mesh.element_type);
  for (FiniteStrainFormulation formulation : formulations(mesh.element_type))
    for (const HyperelasticMaterial& m : kMaterials) {
      const FiniteStrainModel model{mesh, m, kThickness, formulation};
      Eigen::VectorXd force;
      const double energy = internal_force(model, u, force);
      double interior = 0.0;
      for (int i = 0; i < static_cast<int>(mesh.nodes.size()); ++i)
        if (!std::binary_search(boundary.begin(), boundary.end(), i))
          interior = std::max(interior, force.segment(d * i, d).cwiseAbs().maxCoeff());
      const double residual = interior / force.cwiseAbs().maxCoeff();
      EXPECT_LT(residual, 1e-10) << name(mesh.element_type, formulation, m);
      const HyperelasticResponse exact = hyperelastic_response(m, F0);
      EXPECT_NEAR(energy, exact.energy * volume, 1e-10 * exact.energy * volume)
          << name(mesh.element_type, formulation, m);
      EXPECT_NEAR(strain_energy(model, u), energy, 1e-14 * energy);
      Eigen::Matrix3d sigma = exact.stress * F0.transpose() / F0.determinant();
      Stress expected;
      expected << sigma(0, 0), sigma(1, 1), sigma(2, 2), sigma(0, 1), sigma(1, 2), sigma(0, 2);
      for (const Stress& stress : cauchy_stresses(model, u))
        EXPECT_LT((stress - expected).cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff())
            << name(mesh.element_type, formulation, m);
      std::printf("[ measured ] patch %-6s %-16s %-24s interior force / max force %.1e\n",
                  to_string(mesh.element_type), to_string(formulation), to_string(m.law), residual);
    }
}

TEST(FiniteStrainPatchTest, DistortedQuad4) {
  patch_test(test::rectangle(ElementType::quad4, 3, 3, 3.0, 2.0), 0.15);
}
TEST(FiniteStrainPatchTest, DistortedQuad8WithCurvedEdges) {
  patch_test(test::rectangle(ElementType::quad8, 3, 3, 3.0, 2.0), 0.06);
}
TEST(FiniteStrainPatchTest, DistortedHexa8) { patch_test(test::box(2, 2, 2, 1.0, 1.0, 1.0), 0.08); }

// The linear material with the same small-strain moduli.
ElasticMaterial linearized(const HyperelasticMaterial& m) {
  const InitialModuli moduli = initial_moduli(m);
  const double poisson = moduli.lambda / (2.0 * (moduli.lambda + moduli.mu));
  return {2.0 * moduli.mu * (1.0 + poisson), poisson, m.density};
}

TEST(FiniteStrainElement, SmallStrainLimitIsTheLinearElement) {
  for (ElementType type : kTypes)
    for (bool distorted : {false, true}) {
      const ElementGeometry element = single_element(type, distorted);
      const int n = static_cast<int>(element.coordinates.rows()) * dimension_of(type);
      ElementVector tiny(n);
      for (int r = 0; r < n; ++r) tiny(r) = 1e-8 * std::cos(1.3 * r + 0.2);  // m
      for (const HyperelasticMaterial& m : kMaterials) {
        const ElasticMaterial linear = linearized(m);
        const ElementMatrix K = element_stiffness(element, linear, kThickness);
        const double scale = K.cwiseAbs().maxCoeff();
        // At u = 0 exactly (every law), and at a tiny u (the first-order change is O(u/L)).
        const FiniteStrainElementResult rest = finite_strain_element(
            element, m, kThickness, FiniteStrainFormulation::standard, ElementVector::Zero(n));
        EXPECT_LT((rest.tangent - K).cwiseAbs().maxCoeff(), 1e-10 * scale) << to_string(m.law);
        const FiniteStrainElementResult r =
            finite_strain_element(element, m, kThickness, FiniteStrainFormulation::standard, tiny);
        EXPECT_LT((r.tangent - K).cwiseAbs().maxCoeff(), 1e-6 * scale) << to_string(m.law);
        const ElementVector linear_force = K * tiny;
        EXPECT_LT((r.force - linear_force).cwiseAbs().maxCoeff(),
                  1e-6 * linear_force.cwiseAbs().maxCoeff())
            << to_string(m.law);
        const Stress sigma =
            finite_strain_centroid_stress(element, m, FiniteStrainFormulation::standard, tiny);
        const Stress linear_sigma = element_centroid_stress(element, linear, tiny);
        EXPECT_LT((sigma - linear_sigma).cwiseAbs().maxCoeff(),
                  1e-6 * linear_sigma.cwiseAbs().maxCoeff())
            << to_string(m.law);
      }
    }
}

// Q1/P0, Q2/P0 and Q2/P1 at rest: symmetric positive semi-definite with exactly the rigid-body
// modes as null space (no spurious mechanism from the projected dilatation).
TEST(FiniteStrainElement, MixedElementsAtRestHaveOnlyRigidModes) {
  for (ElementType type : kTypes)
    for (FiniteStrainFormulation formulation : formulations(type))
    for (const HyperelasticMaterial& m : {kNeoHookean, kMooneyRivlin}) {
      if (formulation == FiniteStrainFormulation::standard) continue;
      const ElementGeometry element = single_element(type, true);
      const int d = dimension_of(type), n = static_cast<int>(element.coordinates.rows()) * d;
      const ElementMatrix K =
          finite_strain_element(element, m, kThickness, formulation, ElementVector::Zero(n))
              .tangent;
      const Eigen::JacobiSVD<Eigen::MatrixXd, Eigen::NoQRPreconditioner> svd{Eigen::MatrixXd(K)};
      const Eigen::VectorXd sigma = svd.singularValues();
      EXPECT_NEAR(sigma.sum(), K.trace(), 1e-12 * K.trace()) << to_string(type);  // no λ < 0
      // The smallest non-rigid mode is a shear one (~μ); the bulk modes are ~K ≫ μ.
      int zero = 0;
      for (int i = 0; i < sigma.size(); ++i)
        if (sigma(i) < 1e-8 * initial_moduli(m).mu) ++zero;
      EXPECT_EQ(zero, d == 2 ? 3 : 6) << name(type, formulation, m);
    }
}

// The mesh functions: a scatter of the element kernels, consistent with each other and with
// differences of the assembled energy and force.
TEST(FiniteStrainMesh, AssemblyMatchesDifferencesOfEnergyAndForce) {
  for (ElementType type : kTypes) {
    Mesh mesh = type == ElementType::hexa8 ? test::box(2, 1, 1, 2.0, 1.0, 1.0)
                                           : test::rectangle(type, 2, 2, 2.0, 1.0);
    test::distort(mesh, 0.08);
    const int n = mesh.dof_count(), d = mesh.dimension();
    const Eigen::Matrix3d F0 = moderate_gradient(d);
    Eigen::VectorXd u(n);
    for (int i = 0; i < static_cast<int>(mesh.nodes.size()); ++i)
      u.segment(d * i, d) = ((F0 - Eigen::Matrix3d::Identity()) * mesh.nodes[i]).head(d);
    for (int r = 0; r < n; ++r) u(r) += 0.03 * std::sin(1.7 * r);
    const FiniteStrainModel model{mesh, kMooneyRivlin, kThickness,
                                  type == ElementType::quad8
                                      ? FiniteStrainFormulation::linear_dilatation
                                      : FiniteStrainFormulation::mean_dilatation};
    Eigen::VectorXd force, force_only;
    std::vector<Eigen::Triplet<double>> triplets, triplets_only;
    const double energy = assemble_finite_strain(model, u, force, triplets);
    EXPECT_EQ(strain_energy(model, u), energy);
    EXPECT_EQ(internal_force(model, u, force_only), energy);
    EXPECT_EQ((force_only - force).cwiseAbs().maxCoeff(), 0.0);
    tangent_triplets(model, u, triplets_only);
    ASSERT_EQ(triplets_only.size(), triplets.size());
    Eigen::SparseMatrix<double> K(n, n);
    K.setFromTriplets(triplets.begin(), triplets.end());
    const Eigen::MatrixXd tangent(K);
    const double h = 1e-6;
    Eigen::VectorXd force_fd(n);
    Eigen::MatrixXd tangent_fd(n, n);
    for (int c = 0; c < n; ++c) {
      Eigen::VectorXd plus = u, minus = u, force_plus, force_minus;
      plus(c) += h, minus(c) -= h;
      force_fd(c) =
          (internal_force(model, plus, force_plus) - internal_force(model, minus, force_minus)) /
          (2 * h);
      tangent_fd.col(c) = (force_plus - force_minus) / (2 * h);
    }
    EXPECT_LT((force_fd - force).cwiseAbs().maxCoeff(), 1e-6 * force.cwiseAbs().maxCoeff())
        << to_string(type);
    EXPECT_LT((tangent_fd - tangent).cwiseAbs().maxCoeff(), 1e-6 * tangent.cwiseAbs().maxCoeff())
        << to_string(type);
  }
}

void expect_error(const std::function<void()>& call, const std::string& text) {
  try {
    call();
    ADD_FAILURE() << "no error, expected: " << text;
  } catch (const FemError& error) {
    EXPECT_NE(std::string(error.what()).find(text), std::string::npos) << error.what();
  }
}

// The renumbered assembly (a body's free dofs): the plain assembly's triplets with the fixed dofs left
// out and the others renumbered, in the same order and with the same values, appended after what the
// list held.
TEST(FiniteStrainMesh, RenumberedAssemblyKeepsThePlainOnesEntriesInOrder) {
  for (ElementType type : kTypes) {
    Mesh mesh = type == ElementType::hexa8 ? test::box(2, 1, 1, 2.0, 1.0, 1.0)
                                           : test::rectangle(type, 2, 2, 2.0, 1.0);
    test::distort(mesh, 0.05);
    const int n = mesh.dof_count();
    Eigen::VectorXd u(n);
    for (int r = 0; r < n; ++r) u(r) = 0.02 * std::sin(1.3 * r);
    const FiniteStrainModel model{mesh, kMooneyRivlin, kThickness, FiniteStrainFormulation::standard};
    std::vector<int> numbering(n);
    int free = 0;
    for (int r = 0; r < n; ++r) numbering[r] = r % 5 == 1 ? -1 : free++;  // every fifth dof fixed
    Eigen::VectorXd force, force_numbered;
    std::vector<Eigen::Triplet<double>> plain, numbered{{0, 0, 7.0}};
    const double energy = assemble_finite_strain(model, u, force, plain);
    EXPECT_EQ(assemble_finite_strain(model, u, force_numbered, {numbering, 3}, numbered), energy);
    EXPECT_EQ((force_numbered - force).cwiseAbs().maxCoeff(), 0.0);
    std::vector<Eigen::Triplet<double>> expected{{0, 0, 7.0}};
    for (const auto& t : plain)
      if (numbering[t.row()] >= 0 && numbering[t.col()] >= 0)
        expected.emplace_back(3 + numbering[t.row()], 3 + numbering[t.col()], t.value());
    ASSERT_EQ(numbered.size(), expected.size());
    for (std::size_t k = 0; k < expected.size(); ++k) {
      EXPECT_EQ(numbered[k].row(), expected[k].row());
      EXPECT_EQ(numbered[k].col(), expected[k].col());
      EXPECT_EQ(numbered[k].value(), expected[k].value());
    }
    const std::vector<int> short_numbering(n - 1, 0);
    EXPECT_THROW(assemble_finite_strain(model, u, force, {short_numbering, 0}, numbered), FemError);
  }
}

TEST(FiniteStrainElement, InvertedElementsAndBadInputsThrow) {
  for (ElementType type : {ElementType::quad4, ElementType::quad8}) {
    Mesh mesh = test::rectangle(type, 3, 1, 3.0, 1.0);
    // Mirroring element 1 (F = diag(−1, 1)) inverts it.
    const ElementGeometry element = element_geometry(mesh, 1);
    Eigen::Matrix3d mirror = Eigen::Matrix3d::Identity();
    mirror(0, 0) = -1.0;
    const ElementVector flipped = affine_displacement(element.coordinates, mirror, {6, 0, 0}, 2);
    for (FiniteStrainFormulation formulation : formulations(type)) {
      expect_error(
          [&] { finite_strain_element(element, kNeoHookean, kThickness, formulation, flipped); },
          "element 1 is inverted: det F = ");
      expect_error(
          [&] { finite_strain_centroid_stress(element, kNeoHookean, formulation, flipped); },
          "element 1 is inverted");
    }
    // Through the mesh: the bottom-right corner (only in element 2) pushed 2.5 m to the left.
    Eigen::VectorXd u = Eigen::VectorXd::Zero(mesh.dof_count());
    const int corner = mesh.elements[2][1];
    u(2 * corner) = -2.5;
    const FiniteStrainModel model{mesh, kMooneyRivlin, kThickness,
                                  FiniteStrainFormulation::mean_dilatation};
    expect_error([&] { strain_energy(model, u); }, "element 2 is inverted");
    expect_error([&] { strain_energy(model, Eigen::VectorXd::Zero(3)); }, "the displacement has 3");
    const FiniteStrainModel thin{mesh, kMooneyRivlin, 0.0, FiniteStrainFormulation::standard};
    expect_error([&] { strain_energy(thin, Eigen::VectorXd::Zero(mesh.dof_count())); },
                 "thickness = 0");
    if (type == ElementType::quad4) {
      const FiniteStrainModel q1p1{mesh, kMooneyRivlin, kThickness,
                                   FiniteStrainFormulation::linear_dilatation};
      expect_error([&] { strain_energy(q1p1, Eigen::VectorXd::Zero(mesh.dof_count())); },
                   "a linear dilatation (Q2/P1) needs quad8 elements, not quad4");
    }
    HyperelasticMaterial bad = kMooneyRivlin;
    bad.bulk = -1.0;
    const FiniteStrainModel bad_material{mesh, bad, kThickness, FiniteStrainFormulation::standard};
    expect_error([&] { strain_energy(bad_material, Eigen::VectorXd::Zero(mesh.dof_count())); },
                 "bulk =");
  }
}

// ---- volumetric locking -------------------------------------------------------------------------

// Tip deflection (m, downward positive, mean over the tip nodes) of a plane-strain cantilever
// [0, L] × [0, H], clamped at x = 0, under a total downward shear load P (N) spread uniformly over
// the tip, by Newton's method in two load increments.
//
// Convergence is judged on the correction, ‖du‖ ≤ 1e-9 ‖u‖ (reached in 3 iterations), and the
// final residual is checked against 1e-4 ‖f_ext‖ only: with K = 1e4 μ0 the volumetric stresses
// K (J − 1) carry a round-off of ~K ε ≈ 1e-6 Pa that puts a floor of ~2e-5 ‖f_ext‖ (measured) under
// the residual of this small load.
double cantilever_tip_deflection(ElementType type, int nx, int ny,
                                 FiniteStrainFormulation formulation,
                                 const HyperelasticMaterial& material, double length, double height,
                                 double thickness, double load) {
  Mesh mesh = test::rectangle(type, nx, ny, length, height);
  const int n = mesh.dof_count();
  // Consistent nodal forces of a uniform traction: ½, ½ on a 2-node edge; ⅙, ⅙, ⅔ on a 3-node one.
  Eigen::VectorXd external = Eigen::VectorXd::Zero(n);
  const double traction = load / height;  // N/m along the tip edge
  for (const Face& face : mesh.face_sets["right"]) {
    const double edge = (mesh.nodes[face.nodes[1]] - mesh.nodes[face.nodes[0]]).norm();
    const std::vector<double> share = face.nodes.size() == 2
                                          ? std::vector<double>{0.5, 0.5}
                                          : std::vector<double>{1.0 / 6, 1.0 / 6, 2.0 / 3};
    for (std::size_t a = 0; a < face.nodes.size(); ++a)
      external(2 * face.nodes[a] + 1) -= traction * edge * share[a];
  }
  std::vector<int> free_index(n, 0);
  for (int node : mesh.node_sets["left"]) free_index[2 * node] = free_index[2 * node + 1] = -1;
  int free_count = 0;
  for (int& index : free_index)
    if (index == 0) index = free_count++;

  const FiniteStrainModel model{mesh, material, thickness, formulation};
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n), force;
  std::vector<Eigen::Triplet<double>> triplets, free_triplets;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  auto residual_at = [&](const Eigen::VectorXd& target) {
    Eigen::VectorXd residual(free_count);
    for (int dof = 0; dof < n; ++dof)
      if (free_index[dof] >= 0) residual(free_index[dof]) = force(dof) - target(dof);
    return residual;
  };
  const int increments = 2;
  for (int step = 1; step <= increments; ++step) {
    const Eigen::VectorXd target = (static_cast<double>(step) / increments) * external;
    bool converged = false;
    for (int iteration = 0; iteration < 8 && !converged; ++iteration) {
      assemble_finite_strain(model, u, force, triplets);
      free_triplets.clear();
      for (const auto& t : triplets)
        if (free_index[t.row()] >= 0 && free_index[t.col()] >= 0)
          free_triplets.emplace_back(free_index[t.row()], free_index[t.col()], t.value());
      Eigen::SparseMatrix<double> K(free_count, free_count);
      K.setFromTriplets(free_triplets.begin(), free_triplets.end());
      solver.compute(K);
      EXPECT_EQ(solver.info(), Eigen::Success);
      const Eigen::VectorXd correction = solver.solve(residual_at(target));
      for (int dof = 0; dof < n; ++dof)
        if (free_index[dof] >= 0) u(dof) -= correction(free_index[dof]);
      converged = correction.norm() <= 1e-9 * u.norm();
    }
    EXPECT_TRUE(converged) << "Newton, load step " << step;
    internal_force(model, u, force);
    EXPECT_LT(residual_at(target).norm(), 1e-4 * external.norm()) << "load step " << step;
  }
  double deflection = 0.0;
  const std::vector<int>& tip = mesh.node_sets["right"];
  for (int node : tip) deflection -= u(2 * node + 1);
  return deflection / static_cast<double>(tip.size());
}

// Timoshenko: δ = P L³ / (3 E' I) + P L / (κ G A), plane strain E' = E / (1 − ν²), κ = 5/6,
// I = t H³ / 12, A = t H; E, ν, G from the initial moduli.
double timoshenko_deflection(const HyperelasticMaterial& material, double length, double height,
                             double thickness, double load) {
  const InitialModuli moduli = initial_moduli(material);
  const double nu = moduli.lambda / (2.0 * (moduli.lambda + moduli.mu));
  const double young = 2.0 * moduli.mu * (1.0 + nu);
  const double plane_young = young / (1.0 - nu * nu);
  const double inertia = thickness * height * height * height / 12.0;
  return load * length * length * length / (3.0 * plane_young * inertia) +
         load * length / (5.0 / 6.0 * moduli.mu * thickness * height);
}

TEST(FiniteStrainLocking, NearlyIncompressibleCantileverAgainstTimoshenko) {
  const double length = 10.0, height = 1.0, thickness = 1.0;  // m
  // Mooney–Rivlin with K = 1e4 μ0 (ν ≈ 0.49995) and neo-Hookean with ν = 0.4999.
  const HyperelasticMaterial rubber = mooney_rivlin(0.4e6, 0.1e6, 1.0e10, 1100.0);
  const HyperelasticMaterial neo = neo_hookean(3.0e6, 0.4999, 1100.0);
  // A load of deflection ~ L / 10⁴: geometric nonlinearity ~ 1e-8, the response is linear.
  const double load = 1.0;  // N
  struct Case {
    ElementType type;
    int nx, ny;
    FiniteStrainFormulation formulation;
    const HyperelasticMaterial& material;
    double low, high;  // accepted range of the ratio to Timoshenko
  };
  const FiniteStrainFormulation standard = FiniteStrainFormulation::standard;
  const FiniteStrainFormulation mean = FiniteStrainFormulation::mean_dilatation;
  const FiniteStrainFormulation linear = FiniteStrainFormulation::linear_dilatation;
  // The 2D solution itself converges to ≈ 0.985 of Timoshenko (quad4 and quad8 mean dilatation
  // at 160×32 and 80×16): the clamped end and the uniform tip traction, not the elements.
  // Q2/P0 converges to it from above: one pressure per element leaves the linear variation of the
  // volume change across an element free, which relaxes bending for elements off the neutral axis
  // (16×2: +21 %, 20×4: +3.6 %, 40×8: −0.1 % for Mooney–Rivlin).
  const Case cases[] = {
      {ElementType::quad8, 40, 8, mean, rubber, 0.98, 1.02},
      {ElementType::quad8, 40, 8, mean, neo, 0.98, 1.02},
      {ElementType::quad8, 20, 4, mean, rubber, 1.0, 1.06},
      // Q2/P1 constrains the linear volume change too and converges from below, without locking,
      // to the same limit (8×1: 0.9465, 16×2: 0.9668, 40×8: 0.9815, 80×16: 0.9834 measured);
      // Q2/P0 with one element through the depth has a spurious soft bending mode (3.84).
      {ElementType::quad8, 8, 1, linear, rubber, 0.93, 0.985},
      {ElementType::quad8, 8, 1, mean, rubber, 2.0, 10.0},
      {ElementType::quad8, 16, 2, linear, rubber, 0.95, 0.985},
      {ElementType::quad8, 16, 2, linear, neo, 0.95, 0.985},
      {ElementType::quad8, 40, 8, linear, rubber, 0.975, 0.99},
      {ElementType::quad4, 40, 8, mean, rubber, 0.95, 1.05},
      {ElementType::quad4, 40, 8, mean, neo, 0.95, 1.05},
      {ElementType::quad4, 40, 8, standard, rubber, 0.0, 0.1},
      {ElementType::quad4, 40, 8, standard, neo, 0.0, 0.15},
      {ElementType::quad8, 20, 4, standard, rubber, 0.0, 0.97},
  };
  for (const Case& c : cases) {
    const double theory = timoshenko_deflection(c.material, length, height, thickness, load);
    const double deflection = cantilever_tip_deflection(
        c.type, c.nx, c.ny, c.formulation, c.material, length, height, thickness, load);
    const double ratio = deflection / theory;
    std::printf(
        "[ measured ] cantilever %-6s %2dx%d %-16s %-24s δ = %.6e m, Timoshenko %.6e m, "
        "ratio %.4f\n",
        to_string(c.type), c.nx, c.ny, to_string(c.formulation), to_string(c.material.law),
        deflection, theory, ratio);
    EXPECT_GT(ratio, c.low) << to_string(c.type) << " " << to_string(c.formulation);
    EXPECT_LT(ratio, c.high) << to_string(c.type) << " " << to_string(c.formulation);
  }
}

}  // namespace
}  // namespace csim
