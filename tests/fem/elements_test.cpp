// Elements of fem/elements.h against properties they must have whatever the geometry: partition of
// unity, exact quadrature, mass totals, rigid-body modes, the patch test (Zienkiewicz & Taylor vol.
// 1, ch. 10), and the errors on inverted elements and incompressible materials.
#include "fem/elements.h"

#include "fem/assembly.h"
#include "tests/fem/test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace csim {
namespace {

const ElementType kTypes[] = {ElementType::quad4, ElementType::quad8, ElementType::hexa8};
const ElasticMaterial kSteel{2.1e11, 0.3, 7800.0};  // Pa, -, kg/m³
constexpr double kThickness = 0.2;                  // m

int dimension_of(ElementType type) { return type == ElementType::hexa8 ? 3 : 2; }

// One element of 2 × 1 (× 0.5) m, optionally with every node moved by up to 0.15 m.
ElementGeometry single_element(ElementType type, bool distorted) {
  Mesh mesh = type == ElementType::hexa8 ? test::box(1, 1, 1, 2.0, 1.0, 0.5)
                                         : test::rectangle(type, 1, 1, 2.0, 1.0);
  if (distorted) test::distort(mesh, 0.15);
  return element_geometry(mesh, 0);
}

// Volume (m³) by the element's own quadrature of det J: exact for these elements' polynomials.
double quadrature_volume(const ElementGeometry& element) {
  const std::vector<double> det = jacobian_determinants(element);
  const std::vector<GaussPoint> rule = gauss_rule(element.type);
  double volume = 0.0;
  for (std::size_t g = 0; g < rule.size(); ++g) volume += rule[g].weight * det[g];
  return dimension_of(element.type) == 2 ? volume * kThickness : volume;
}

std::vector<Eigen::Vector3d> random_points(int count) {
  std::mt19937 generator(12345);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i)
    points.emplace_back(uniform(generator), uniform(generator), uniform(generator));
  return points;
}

TEST(ShapeFunctions, PartitionOfUnityAndZeroDerivativeSums) {
  for (ElementType type : kTypes) {
    for (const Eigen::Vector3d& xi : random_points(20)) {
      const ShapeFunctions s = shape_functions(type, xi);
      EXPECT_NEAR(s.values.sum(), 1.0, 1e-14) << to_string(type);
      for (int j = 0; j < dimension_of(type); ++j)
        EXPECT_NEAR(s.derivatives.col(j).sum(), 0.0, 1e-14)
            << to_string(type) << " direction " << j;
    }
  }
}

TEST(ShapeFunctions, DerivativesMatchCentralDifferences) {
  const double h = 1e-6;
  for (ElementType type : kTypes) {
    for (const Eigen::Vector3d& xi : random_points(10)) {
      const ShapeFunctions s = shape_functions(type, xi);
      for (int j = 0; j < dimension_of(type); ++j) {
        const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(j);
        const auto difference =
            ((shape_functions(type, xi + step).values - shape_functions(type, xi - step).values) /
             (2 * h))
                .eval();
        EXPECT_LT((difference - s.derivatives.col(j)).cwiseAbs().maxCoeff(), 1e-8)
            << to_string(type);
      }
    }
  }
}

TEST(ShapeFunctions, KroneckerAtTheNodes) {
  for (ElementType type : kTypes) {
    const std::vector<Eigen::Vector3d> nodes = reference_nodes(type);
    ASSERT_EQ(nodes.size(), type == ElementType::quad4 ? 4u : 8u);
    for (std::size_t b = 0; b < nodes.size(); ++b) {
      const ShapeFunctions s = shape_functions(type, nodes[b]);
      for (std::size_t a = 0; a < nodes.size(); ++a)
        EXPECT_NEAR(s.values(a), a == b ? 1.0 : 0.0, 1e-15)
            << to_string(type) << " N" << a << " at node " << b;
    }
  }
}

double exact_monomial_integral(int power) { return power % 2 == 1 ? 0.0 : 2.0 / (power + 1); }

TEST(GaussRules, OneDimensionalRulesAreExactToDegreeTwoNMinusOne) {
  for (int n = 1; n <= 4; ++n) {
    const std::vector<GaussPoint> rule = gauss_legendre(n);
    ASSERT_EQ(static_cast<int>(rule.size()), n);
    for (int power = 0; power <= 2 * n; ++power) {
      double sum = 0.0;
      for (const GaussPoint& g : rule) sum += g.weight * std::pow(g.natural.x(), power);
      if (power <= 2 * n - 1)
        EXPECT_NEAR(sum, exact_monomial_integral(power), 1e-15) << n << " points, x^" << power;
      else  // and no further: degree 2n is not integrated exactly
        EXPECT_GT(std::abs(sum - exact_monomial_integral(power)), 1e-3)
            << n << " points, x^" << power;
    }
  }
  EXPECT_THROW(gauss_legendre(5), FemError);
}

TEST(GaussRules, ElementRulesIntegrateTensorMonomialsExactly) {
  for (ElementType type : kTypes) {
    const int points = type == ElementType::quad8 ? 3 : 2, d = dimension_of(type);
    const std::vector<GaussPoint> rule = gauss_rule(type);
    ASSERT_EQ(static_cast<int>(rule.size()), static_cast<int>(std::pow(points, d)));
    const int top = 2 * points - 1, top_z = d == 3 ? top : 0;
    for (int a = 0; a <= top; ++a)
      for (int b = 0; b <= top; ++b)
        for (int c = 0; c <= top_z; ++c) {
          double sum = 0.0;
          for (const GaussPoint& g : rule)
            sum += g.weight * std::pow(g.natural.x(), a) * std::pow(g.natural.y(), b) *
                   (d == 3 ? std::pow(g.natural.z(), c) : 1.0);
          const double exact = exact_monomial_integral(a) * exact_monomial_integral(b) *
                               (d == 3 ? exact_monomial_integral(c) : 1.0);
          EXPECT_NEAR(sum, exact, 1e-14)
              << to_string(type) << " ξ^" << a << " η^" << b << " ζ^" << c;
        }
  }
}

TEST(ElementMass, ConsistentAndLumpedSumToDensityTimesVolumePerDirection) {
  for (ElementType type : kTypes) {
    const int d = dimension_of(type);
    // An affine image of the reference box (volume known independently), then a general distortion.
    Eigen::Matrix3d A;
    A << 1.2, 0.4, 0.1, -0.3, 0.9, 0.2, 0.1, -0.2, 1.1;
    if (d == 2) {  // plane: z untouched
      A.row(2).setZero();
      A.col(2).setZero();
      A(2, 2) = 1.0;
    }
    ElementGeometry affine = single_element(type, false);
    const double box_volume = d == 2 ? 2.0 * 1.0 * kThickness : 2.0 * 1.0 * 0.5;
    for (int a = 0; a < affine.coordinates.rows(); ++a)
      affine.coordinates.row(a) = (A * affine.coordinates.row(a).transpose()).transpose();
    const ElementGeometry distorted = single_element(type, true);
    for (const auto& [element, volume] : {std::pair{affine, box_volume * A.determinant()},
                                          std::pair{distorted, quadrature_volume(distorted)}}) {
      const double mass = kSteel.density * volume;
      const ElementMatrix M = element_consistent_mass(element, kSteel.density, kThickness);
      const ElementVector lumped = element_lumped_mass(element, kSteel.density, kThickness);
      EXPECT_NEAR(M.sum(), d * mass, 1e-12 * mass) << to_string(type);
      EXPECT_NEAR((M - M.transpose()).norm(), 0.0, 1e-12 * mass);
      EXPECT_NEAR(lumped.sum(), d * mass, 1e-12 * mass) << to_string(type);
      EXPECT_GT(lumped.minCoeff(), 0.0) << to_string(type);
    }
  }
}

TEST(ElementMass, Quad8LumpingIsHrzNotRowSum) {
  const ElementGeometry element = single_element(ElementType::quad8, false);
  const double mass = kSteel.density * 2.0 * kThickness;
  const ElementMatrix M = element_consistent_mass(element, kSteel.density, kThickness);
  // Why HRZ: the row sums of the serendipity mass are −m/12 at each corner of a rectangle.
  for (int a = 0; a < 4; ++a) EXPECT_NEAR(M.row(2 * a).sum(), -mass / 12.0, 1e-12 * mass);
  const ElementVector lumped = element_lumped_mass(element, kSteel.density, kThickness);
  // HRZ on a rectangle: corners 3m/76, mid-sides 16m/76 per direction (Hinton et al. 1976).
  for (int a = 0; a < 8; ++a)
    EXPECT_NEAR(lumped(2 * a), (a < 4 ? 3.0 : 16.0) * mass / 76.0, 1e-12 * mass) << "node " << a;
  // A massless material (quasi-static runs) gives zero masses, not 0/0.
  EXPECT_EQ(element_lumped_mass(element, 0.0, kThickness).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_THROW(element_lumped_mass(element, -1.0, kThickness), FemError);
}

TEST(ElementStiffness, SymmetricWithExactlyTheRigidBodyModesAsNullSpace) {
  for (ElementType type : kTypes) {
    for (bool distorted : {false, true}) {
      const ElementGeometry element = single_element(type, distorted);
      const ElementMatrix K = element_stiffness(element, kSteel, kThickness);
      const int d = dimension_of(type), rigid_modes = d == 2 ? 3 : 6;
      EXPECT_EQ((K - K.transpose()).norm(), 0.0) << to_string(type);
      // Singular values of the symmetric K are |λ_i| (a square SVD without QR preconditioner rather
      // than SelfAdjointEigenSolver, whose Householder code trips a GCC 12 -Wmaybe-uninitialized
      // false positive inside Eigen); no λ_i < 0 is then Σ|λ_i| = Σλ_i = trace K.
      const Eigen::JacobiSVD<Eigen::MatrixXd, Eigen::NoQRPreconditioner> svd{Eigen::MatrixXd(K)};
      const Eigen::VectorXd sigma = svd.singularValues();
      const double largest = sigma.maxCoeff();
      EXPECT_NEAR(sigma.sum(), K.trace(), 1e-12 * K.trace()) << to_string(type);
      int zero = 0;
      for (int i = 0; i < sigma.size(); ++i)
        if (sigma(i) < 1e-10 * largest) ++zero;
      EXPECT_EQ(zero, rigid_modes)
          << to_string(type) << (distorted ? " distorted" : " undistorted");
      // The rigid-body motions themselves: translations and small rotations u = ω × x.
      for (int mode = 0; mode < rigid_modes; ++mode) {
        Eigen::VectorXd u(K.rows());
        for (int a = 0; a < element.coordinates.rows(); ++a) {
          const Eigen::Vector3d x = element.coordinates.row(a).transpose();
          const Eigen::Vector3d motion =
              mode < d ? Eigen::Vector3d::Unit(mode).eval()
                       : Eigen::Vector3d::Unit(d == 2 ? 2 : mode - d).cross(x);
          u.segment(d * a, d) = motion.head(d);
        }
        EXPECT_LT((K * u).norm(), 1e-10 * largest * u.norm())
            << to_string(type) << " mode " << mode;
      }
    }
  }
}

// Constant-stress patch test: the boundary nodes of a patch of distorted elements follow
// u = u0 + G x; the interior nodes, solved from K, must follow it too, and every element must carry
// the exact stress σ = D sym(G).
void patch_test(Mesh mesh, double distortion) {
  test::distort(mesh, distortion);
  check_mesh(mesh);
  const ElasticMaterial material{1000.0, 0.3, 1.0};
  const FeModel model{mesh, material, kThickness};
  const int d = mesh.dofs_per_node();
  Eigen::Matrix3d G;
  G << 1.0e-3, 2.0e-3, -0.5e-3, -1.5e-3, 0.5e-3, 1.0e-3, 0.7e-3, -0.3e-3, 2.5e-3;
  const Eigen::Vector3d u0(0.01, -0.02, 0.03);
  Eigen::VectorXd exact(mesh.dof_count());
  for (int i = 0; i < static_cast<int>(mesh.nodes.size()); ++i)
    exact.segment(d * i, d) = (u0 + G * mesh.nodes[i]).head(d);
  std::map<int, double> prescribed;
  for (int node : mesh.node_sets.at("boundary"))
    for (int i = 0; i < d; ++i) prescribed[d * node + i] = exact(d * node + i);
  ASSERT_LT(prescribed.size(), static_cast<std::size_t>(mesh.dof_count()));  // an interior exists

  const Eigen::VectorXd u =
      test::solve(assemble_stiffness(model), Eigen::VectorXd::Zero(mesh.dof_count()), prescribed);
  EXPECT_LT((u - exact).cwiseAbs().maxCoeff(), 1e-10 * exact.cwiseAbs().maxCoeff());

  // σ = λ tr(ε) I + 2μ ε with ε = sym(G) restricted to the plane (εzz = 0) in 2D.
  Eigen::Matrix3d strain = 0.5 * (G + G.transpose());
  if (d == 2) strain.row(2).setZero(), strain.col(2).setZero();
  const Eigen::Matrix3d sigma =
      lame_lambda(material) * strain.trace() * Eigen::Matrix3d::Identity() +
      2.0 * shear_modulus(material) * strain;
  Stress expected;
  expected << sigma(0, 0), sigma(1, 1), sigma(2, 2), sigma(0, 1), d == 3 ? sigma(1, 2) : 0.0,
      d == 3 ? sigma(0, 2) : 0.0;
  for (const Stress& stress : element_stresses(model, u))
    EXPECT_LT((stress - expected).cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff());
}

TEST(PatchTest, DistortedQuad4) {
  patch_test(test::rectangle(ElementType::quad4, 2, 2, 1.0, 1.0), 0.08);
}
TEST(PatchTest, DistortedQuad8WithCurvedEdges) {
  patch_test(test::rectangle(ElementType::quad8, 2, 2, 1.0, 1.0), 0.04);
}
TEST(PatchTest, DistortedHexa8) { patch_test(test::box(2, 2, 2, 1.0, 1.0, 1.0), 0.08); }

// Reverses the node order of element e (counter-clockwise becomes clockwise, top and bottom swap).
void flip(Mesh& mesh, int e) {
  std::vector<int>& n = mesh.elements[e];
  if (mesh.element_type == ElementType::quad4) n = {n[0], n[3], n[2], n[1]};
  if (mesh.element_type == ElementType::quad8) n = {n[0], n[3], n[2], n[1], n[7], n[6], n[5], n[4]};
  if (mesh.element_type == ElementType::hexa8) n = {n[4], n[5], n[6], n[7], n[0], n[1], n[2], n[3]};
}

TEST(Jacobian, InvertedElementThrowsNamingIt) {
  for (ElementType type : kTypes) {
    Mesh mesh = type == ElementType::hexa8 ? test::box(3, 1, 1, 3.0, 1.0, 1.0)
                                           : test::rectangle(type, 3, 1, 3.0, 1.0);
    EXPECT_NO_THROW(check_mesh(mesh));
    flip(mesh, 1);
    const FeModel model{mesh, kSteel, kThickness};
    for (const auto& call : std::vector<std::function<void()>>{
             [&] { check_mesh(mesh); }, [&] { assemble_stiffness(model); },
             [&] { assemble_mass(model, false); }, [&] { assemble_mass(model, true); }}) {
      try {
        call();
        ADD_FAILURE() << to_string(type) << ": no error for an inverted element";
      } catch (const FemError& error) {
        EXPECT_NE(std::string(error.what())
                      .find("element 1 has a non-positive Jacobian (inverted or degenerate)"),
                  std::string::npos)
            << error.what();
      }
    }
  }
}

// A corner given twice collapses the element (a quad4 into a triangle) while its Gauss points can keep
// a positive Jacobian; the collapsed edge or face matches no neighbour's and leaves a hole in the mesh.
TEST(Jacobian, AnElementListingANodeTwiceIsRefused) {
  for (ElementType type : kTypes) {
    Mesh mesh = type == ElementType::hexa8 ? test::box(3, 1, 1, 3.0, 1.0, 1.0)
                                           : test::rectangle(type, 3, 1, 3.0, 1.0);
    mesh.elements[1][2] = mesh.elements[1][1];
    try {
      check_mesh(mesh);
      ADD_FAILURE() << to_string(type) << ": no error for a repeated node";
    } catch (const FemError& error) {
      const std::string expected = "element 1 lists node " + std::to_string(mesh.elements[1][1]) +
                                   " twice: a degenerate " + to_string(type);
      EXPECT_NE(std::string(error.what()).find(expected), std::string::npos) << error.what();
    }
  }
}

TEST(Jacobian, DegenerateAndMalformedElementsThrow) {
  Mesh mesh = test::rectangle(ElementType::quad4, 2, 1, 2.0, 1.0);
  Mesh collinear = mesh;
  for (int a : collinear.elements[0]) collinear.nodes[a].y() = 0.0;
  EXPECT_THROW(check_mesh(collinear), FemError);
  Mesh bad_index = mesh;
  bad_index.elements[1][2] = 99;
  try {
    check_mesh(bad_index);
    ADD_FAILURE() << "no error for a node index out of range";
  } catch (const FemError& error) {
    EXPECT_NE(std::string(error.what()).find("element 1: node index 99"), std::string::npos)
        << error.what();
  }
  Mesh short_element = mesh;
  short_element.elements[0].pop_back();
  EXPECT_THROW(check_mesh(short_element), FemError);
}

TEST(Jacobian, DeterminantsOfARectangleAreItsAreaOverFour) {
  const std::vector<double> det = jacobian_determinants(single_element(ElementType::quad4, false));
  ASSERT_EQ(det.size(), 4u);
  for (double value : det) EXPECT_NEAR(value, 2.0 / 4.0, 1e-15);
}

TEST(Material, IncompressibleAndOutOfRangeValuesThrow) {
  try {
    check_material({2.1e11, 0.5, 7800.0});
    ADD_FAILURE() << "ν = 0.5 accepted";
  } catch (const FemError& error) {
    EXPECT_NE(std::string(error.what()).find("poisson"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("ν must be < 0.5 for a compressible law"),
              std::string::npos);
  }
  EXPECT_THROW(
      element_stiffness(single_element(ElementType::quad4, false), {2.1e11, 0.5, 7800.0}, 1.0),
      FemError);
  EXPECT_THROW(check_material({0.0, 0.3, 7800.0}), FemError);
  EXPECT_THROW(check_material({2.1e11, -1.0, 7800.0}), FemError);
  EXPECT_THROW(check_material({2.1e11, 0.3, -1.0}), FemError);
  EXPECT_THROW(check_material({std::nan(""), 0.3, 7800.0}), FemError);
  EXPECT_NO_THROW(check_material({2.1e11, 0.499, 0.0}));
  EXPECT_NO_THROW(check_material({2.1e11, -0.9, 7800.0}));
}

TEST(ElementStress, RigidRotationIsStressFreeAndThicknessIsChecked) {
  const ElementGeometry element = single_element(ElementType::quad8, true);
  ElementVector u(16);
  for (int a = 0; a < 8; ++a)  // small rotation ω about z: u = (−ω y, ω x)
    u.segment<2>(2 * a) =
        1e-3 * Eigen::Vector2d(-element.coordinates(a, 1), element.coordinates(a, 0));
  EXPECT_LT(element_centroid_stress(element, kSteel, u).cwiseAbs().maxCoeff(),
            1e-12 * kSteel.young);
  EXPECT_THROW(element_stiffness(element, kSteel, 0.0), FemError);
}

// The ParaView output's map gives each element's centroid stress to the bit, on distorted meshes of
// every type and a displacement with all components, and refuses a displacement of another size.
TEST(ElementStress, CentroidStressMapIsElementCentroidStressToTheBit) {
  std::mt19937 random(31);
  std::uniform_real_distribution<double> uniform(-1e-3, 1e-3);
  for (const ElementType type : kTypes) {
    Mesh mesh = type == ElementType::hexa8 ? test::box(3, 2, 2, 2.0, 1.0, 0.5) : test::rectangle(type, 3, 2, 2.0, 1.0);
    test::distort(mesh, 0.08);
    Eigen::VectorXd u(mesh.dof_count());
    for (Eigen::Index i = 0; i < u.size(); ++i) u(i) = uniform(random);
    const CentroidStressMap map(mesh, kSteel);
    std::vector<Stress> stresses(1, Stress::Constant(7.0));  // resized and overwritten
    map.stresses(u, stresses);
    ASSERT_EQ(stresses.size(), mesh.elements.size()) << to_string(type);
    for (int e = 0; e < static_cast<int>(mesh.elements.size()); ++e) {
      const Stress expected = element_centroid_stress(element_geometry(mesh, e), kSteel, element_values(mesh, e, u));
      EXPECT_GT(expected.cwiseAbs().maxCoeff(), 1e5) << to_string(type);  // a strain of order 1e-3
      for (int k = 0; k < 6; ++k) EXPECT_EQ(stresses[e](k), expected(k)) << to_string(type) << " element " << e;
    }
    EXPECT_THROW(map.stresses(Eigen::VectorXd::Zero(u.size() - 1), stresses), FemError) << to_string(type);
  }
}

}  // namespace
}  // namespace csim
