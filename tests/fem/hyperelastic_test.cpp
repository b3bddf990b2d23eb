// Hyperelastic laws of fem/hyperelastic.h: energies against direct formulas in principal stretches,
// P and A against central differences of W and P, the natural state, objectivity, the small-strain
// limit and the checks of the constants.
//
// Tolerances. Central differences with step h on F entries of order 1 have a truncation error
// ~ h² |W'''| and a round-off error ~ ε |W| / h; h = 1e-5 keeps both near 1e-10 relative, so the
// 1e-6 bound fails for any wrong term (a wrong coefficient or index gives errors of order 1) while
// leaving room for the stiffer Mooney–Rivlin bulk term (K = 1e3 μ0). Identities that hold exactly
// (natural state, objectivity, symmetry) are checked to 1e-12 relative, round-off only.
#include "fem/hyperelastic.h"

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace csim {
namespace {

const HyperelasticMaterial kSvk = saint_venant_kirchhoff(2.0e6, 0.3, 1000.0);
const HyperelasticMaterial kNeoHookean = neo_hookean(2.0e6, 0.45, 1000.0);
const HyperelasticMaterial kMooneyRivlin =
    mooney_rivlin(0.4e6, 0.1e6, 1.0e9, 1100.0);  // K = 1e3 μ0
const HyperelasticMaterial kMaterials[] = {kSvk, kNeoHookean, kMooneyRivlin};

// Random 3D deformation gradients F = I + 0.3 R (R uniform in [−1, 1]), det F ≥ 0.3.
std::vector<Eigen::Matrix3d> random_gradients(int count, bool plane_strain = false) {
  std::mt19937 generator(2024);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Matrix3d> gradients;
  while (static_cast<int>(gradients.size()) < count) {
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) F(i, j) += 0.3 * uniform(generator);
    if (plane_strain) {
      F.row(2).setZero(), F.col(2).setZero();
      F(2, 2) = 1.0;
    }
    if (F.determinant() >= 0.3) gradients.push_back(F);
  }
  return gradients;
}

using Response = std::function<HyperelasticResponse(const Eigen::Matrix3d&)>;

// max |P − ∂W/∂F|_FD / max |P| and max |A − ∂P/∂F|_FD / max |A|.
std::pair<double, double> difference_errors(const Response& response, const Eigen::Matrix3d& F) {
  const double h = 1e-5;
  const HyperelasticResponse r = response(F);
  Eigen::Matrix3d P_fd;
  MaterialTangent A_fd;
  for (int k = 0; k < 3; ++k)
    for (int L = 0; L < 3; ++L) {
      Eigen::Matrix3d step = Eigen::Matrix3d::Zero();
      step(k, L) = h;
      const HyperelasticResponse plus = response(F + step), minus = response(F - step);
      P_fd(k, L) = (plus.energy - minus.energy) / (2 * h);
      for (int i = 0; i < 3; ++i)
        for (int J = 0; J < 3; ++J)
          A_fd(3 * i + J, 3 * k + L) = (plus.stress(i, J) - minus.stress(i, J)) / (2 * h);
    }
  return {(P_fd - r.stress).cwiseAbs().maxCoeff() / r.stress.cwiseAbs().maxCoeff(),
          (A_fd - r.tangent).cwiseAbs().maxCoeff() / r.tangent.cwiseAbs().maxCoeff()};
}

TEST(HyperelasticLaw, StressAndTangentMatchCentralDifferences) {
  for (const HyperelasticMaterial& m : kMaterials) {
    double worst_stress = 0.0, worst_tangent = 0.0;
    for (bool plane : {false, true})
      for (const Eigen::Matrix3d& F : random_gradients(6, plane)) {
        for (const Response& response :
             {Response([&](const Eigen::Matrix3d& G) { return hyperelastic_response(m, G); }),
              Response([&](const Eigen::Matrix3d& G) { return isochoric_response(m, G); })}) {
          const auto [stress, tangent] = difference_errors(response, F);
          worst_stress = std::max(worst_stress, stress);
          worst_tangent = std::max(worst_tangent, tangent);
        }
      }
    EXPECT_LT(worst_stress, 1e-6) << to_string(m.law);
    EXPECT_LT(worst_tangent, 1e-6) << to_string(m.law);
    std::printf("[ measured ] %-24s FD relative error: P %.2e, A %.2e\n", to_string(m.law),
                worst_stress, worst_tangent);
  }
}

// In-plane gradients F2 of large strains and rotations: half F2 = R U, U symmetric with principal
// stretches between 1/5 and 5 along random axes, R any rotation; half unstructured, F2 = I + 2 R
// (R uniform in [−1, 1]) with det F2 ≥ 0.05.
std::vector<Eigen::Matrix2d> random_plane_gradients(int count) {
  std::mt19937 generator(31);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Matrix2d> gradients;
  while (static_cast<int>(gradients.size()) < count) {
    if (gradients.size() % 2 == 0) {
      const Eigen::Matrix2d axes = Eigen::Rotation2Dd(M_PI * uniform(generator)).toRotationMatrix();
      const Eigen::Vector2d stretches(std::pow(5.0, uniform(generator)),
                                      std::pow(5.0, uniform(generator)));
      const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(M_PI * uniform(generator)).toRotationMatrix();
      gradients.push_back(rotation * axes * stretches.asDiagonal() * axes.transpose());
    } else {
      Eigen::Matrix2d F = Eigen::Matrix2d::Identity();
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) F(i, j) += 2.0 * uniform(generator);
      if (F.determinant() >= 0.05) gradients.push_back(F);
    }
  }
  return gradients;
}

// The plane-strain response (D = 2, 2×2 algebra on F's in-plane block) is the general 3D one at
// F = [[F2, 0], [0, 1]] on the in-plane indices: energy, P's in-plane block and A's, each to round-off
// of its scale (the largest entry of the whole P or A, the largest energy term). A dropped or wrong
// term, a missing out-of-plane 1 in a trace, is off by O(1) of that scale.
TEST(HyperelasticLaw, PlaneStrainIsTheGeneralLawInPlane) {
  for (const HyperelasticMaterial& m : kMaterials) {
    double worst_energy = 0.0, worst_stress = 0.0, worst_tangent = 0.0;
    for (const Eigen::Matrix2d& F2 : random_plane_gradients(200)) {
      Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
      F.topLeftCorner<2, 2>() = F2;
      for (bool whole_law : {true, false}) {
        const HyperelasticResponse full =
            whole_law ? hyperelastic_response(m, F) : isochoric_response(m, F);
        const HyperelasticResponseOf<2> plane =
            whole_law ? hyperelastic_response<2>(m, F2) : isochoric_response<2>(m, F2);
        // W's terms are of order (modulus) × (I1 + I2 + 1) even where they cancel.
        const InitialModuli moduli = initial_moduli(m);
        const double invariants = F.squaredNorm() + 0.5 * std::pow(F.squaredNorm(), 2) + 1.0;
        const double energy_scale = (std::abs(moduli.lambda) + moduli.mu) * invariants;
        worst_energy = std::max(worst_energy, std::abs(plane.energy - full.energy) / energy_scale);
        worst_stress = std::max(worst_stress, (plane.stress - full.stress.topLeftCorner<2, 2>())
                                                      .cwiseAbs()
                                                      .maxCoeff() /
                                                  full.stress.cwiseAbs().maxCoeff());
        double tangent = 0.0;
        for (int i = 0; i < 2; ++i)
          for (int J = 0; J < 2; ++J)
            for (int k = 0; k < 2; ++k)
              for (int L = 0; L < 2; ++L)
                tangent = std::max(tangent, std::abs(plane.tangent(2 * i + J, 2 * k + L) -
                                                     full.tangent(3 * i + J, 3 * k + L)));
        worst_tangent = std::max(worst_tangent, tangent / full.tangent.cwiseAbs().maxCoeff());
        const HyperelasticResponseOf<2> no_tangent =
            whole_law ? hyperelastic_response<2>(m, F2, false) : isochoric_response<2>(m, F2, false);
        EXPECT_EQ(no_tangent.energy, plane.energy) << to_string(m.law);
        EXPECT_EQ(no_tangent.stress, plane.stress) << to_string(m.law);
        EXPECT_TRUE(no_tangent.tangent.isZero(0.0)) << to_string(m.law);
      }
    }
    EXPECT_LT(worst_energy, 1e-13) << to_string(m.law);
    EXPECT_LT(worst_stress, 1e-13) << to_string(m.law);
    EXPECT_LT(worst_tangent, 1e-13) << to_string(m.law);
    std::printf("[ measured ] %-24s plane strain vs 3D, relative: W %.1e, P %.1e, A %.1e\n",
                to_string(m.law), worst_energy, worst_stress, worst_tangent);
  }
}

TEST(HyperelasticLaw, VolumetricDerivativesMatchCentralDifferences) {
  const double h = 1e-6;
  for (const HyperelasticMaterial& m : {kNeoHookean, kMooneyRivlin})
    for (double J : {0.6, 0.95, 1.0, 1.3}) {
      const VolumetricResponse r = volumetric_response(m, J);
      const VolumetricResponse plus = volumetric_response(m, J + h),
                               minus = volumetric_response(m, J - h);
      const double scale = std::abs(r.stiffness);
      EXPECT_NEAR((plus.energy - minus.energy) / (2 * h), r.mean_stress, 1e-7 * scale);
      EXPECT_NEAR((plus.mean_stress - minus.mean_stress) / (2 * h), r.stiffness, 1e-7 * scale);
    }
  const VolumetricResponse none = volumetric_response(kSvk, 1.2);
  EXPECT_EQ(none.energy, 0.0);
  EXPECT_EQ(none.mean_stress, 0.0);
}

// The energies themselves, from the principal stretches: independent of the tensor code.
TEST(HyperelasticLaw, EnergiesMatchPrincipalStretchFormulas) {
  for (const Eigen::Matrix3d& F : random_gradients(5)) {
    // C is symmetric positive definite: its singular values are its eigenvalues, the squared
    // principal stretches.
    const Eigen::Vector3d squares =
        Eigen::JacobiSVD<Eigen::Matrix3d>(F.transpose() * F).singularValues();
    const double J = std::sqrt(squares.prod());
    const double I1 = squares.sum();
    const double I2 = squares(0) * squares(1) + squares(1) * squares(2) + squares(0) * squares(2);
    const Eigen::Vector3d green = 0.5 * (squares.array() - 1.0);
    const double svk =
        0.5 * kSvk.lambda * green.sum() * green.sum() + kSvk.mu * green.squaredNorm();
    const double nh = 0.5 * kNeoHookean.mu * (I1 - 3) - kNeoHookean.mu * std::log(J) +
                      0.5 * kNeoHookean.lambda * std::log(J) * std::log(J);
    const HyperelasticMaterial& mr = kMooneyRivlin;
    const double mooney = mr.c10 * (std::pow(J, -2.0 / 3.0) * I1 - 3) +
                          mr.c01 * (std::pow(J, -4.0 / 3.0) * I2 - 3) +
                          0.5 * mr.bulk * (J - 1) * (J - 1);
    EXPECT_NEAR(hyperelastic_response(kSvk, F).energy, svk, 1e-12 * std::abs(svk));
    EXPECT_NEAR(hyperelastic_response(kNeoHookean, F).energy, nh, 1e-12 * std::abs(nh));
    EXPECT_NEAR(hyperelastic_response(mr, F).energy, mooney, 1e-11 * std::abs(mooney));
  }
}

// Lamé form C_iJkL = λ δiJ δkL + μ (δik δJL + δiL δkJ).
MaterialTangent isotropic_tangent(double lambda, double mu) {
  MaterialTangent C = MaterialTangent::Zero();
  auto delta = [](int a, int b) { return a == b ? 1.0 : 0.0; };
  for (int i = 0; i < 3; ++i)
    for (int J = 0; J < 3; ++J)
      for (int k = 0; k < 3; ++k)
        for (int L = 0; L < 3; ++L)
          C(3 * i + J, 3 * k + L) = lambda * delta(i, J) * delta(k, L) +
                                    mu * (delta(i, k) * delta(J, L) + delta(i, L) * delta(k, J));
  return C;
}

TEST(HyperelasticLaw, NaturalStateIsStressFreeWithTheLinearIsotropicTangent) {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  for (const HyperelasticMaterial& m : kMaterials) {
    const InitialModuli moduli = initial_moduli(m);
    const MaterialTangent expected = isotropic_tangent(moduli.lambda, moduli.mu);
    for (const Response& response :
         {Response([&](const Eigen::Matrix3d& G) { return hyperelastic_response(m, G); }),
          Response([&](const Eigen::Matrix3d& G) { return isochoric_response(m, G); })}) {
      const HyperelasticResponse r = response(I);
      EXPECT_NEAR(r.energy, 0.0, 1e-12 * moduli.mu) << to_string(m.law);
      EXPECT_LT(r.stress.cwiseAbs().maxCoeff(), 1e-12 * moduli.mu) << to_string(m.law);
    }
    const HyperelasticResponse r = hyperelastic_response(m, I);
    EXPECT_LT((r.tangent - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff())
        << to_string(m.law);
    EXPECT_NEAR(volumetric_response(m, 1.0).mean_stress, 0.0, 1e-12 * moduli.mu);
  }
  // Mooney–Rivlin: μ0 = 2(C10 + C01), bulk K.
  const InitialModuli mr = initial_moduli(kMooneyRivlin);
  EXPECT_DOUBLE_EQ(mr.mu, 1.0e6);
  EXPECT_DOUBLE_EQ(mr.lambda + 2.0 / 3.0 * mr.mu, 1.0e9);
}

TEST(HyperelasticLaw, ObjectiveAndMajorSymmetric) {
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  for (const HyperelasticMaterial& m : kMaterials)
    for (const Eigen::Matrix3d& F : random_gradients(4)) {
      const HyperelasticResponse r = hyperelastic_response(m, F);
      const HyperelasticResponse rotated = hyperelastic_response(m, R * F);
      EXPECT_NEAR(rotated.energy, r.energy, 1e-12 * std::abs(r.energy)) << to_string(m.law);
      const double scale = r.stress.cwiseAbs().maxCoeff();
      EXPECT_LT((rotated.stress - R * r.stress).cwiseAbs().maxCoeff(), 1e-12 * scale)
          << to_string(m.law);
      EXPECT_LT((r.tangent - r.tangent.transpose()).cwiseAbs().maxCoeff(),
                1e-12 * r.tangent.cwiseAbs().maxCoeff())
          << to_string(m.law);
    }
}

TEST(HyperelasticLaw, InvertedMaterialPointThrows) {
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(0, 0) = -0.5;
  for (const HyperelasticMaterial& m : kMaterials) {
    EXPECT_THROW(hyperelastic_response(m, F), FemError) << to_string(m.law);
    EXPECT_THROW(isochoric_response(m, F), FemError) << to_string(m.law);
    const Eigen::Matrix2d plane = F.topLeftCorner<2, 2>();
    EXPECT_THROW(hyperelastic_response<2>(m, plane), FemError) << to_string(m.law);
    EXPECT_THROW(isochoric_response<2>(m, plane), FemError) << to_string(m.law);
    EXPECT_THROW(volumetric_response(m, 0.0), FemError) << to_string(m.law);
  }
}

void expect_rejected(const std::function<void()>& make, const std::string& key) {
  try {
    make();
    ADD_FAILURE() << "no error for " << key;
  } catch (const FemError& error) {
    EXPECT_NE(std::string(error.what()).find(key + " ="), std::string::npos) << error.what();
  }
}

TEST(HyperelasticMaterialCheck, RejectsBadValuesNamingTheKey) {
  const double nan = std::nan("");
  expect_rejected([] { neo_hookean(0.0, 0.3, 1000.0); }, "young");
  expect_rejected([] { neo_hookean(1e6, 0.5, 1000.0); }, "poisson");
  expect_rejected([] { saint_venant_kirchhoff(1e6, -1.0, 1000.0); }, "poisson");
  expect_rejected([] { saint_venant_kirchhoff(1e6, 0.3, -1.0); }, "density");
  expect_rejected([&] { neo_hookean(nan, 0.3, 1000.0); }, "young");
  expect_rejected([] { mooney_rivlin(0.1e6, -0.1e6, 1e9, 1000.0); }, "c10");
  expect_rejected([] { mooney_rivlin(0.4e6, 0.1e6, 0.0, 1000.0); }, "bulk");
  expect_rejected([&] { mooney_rivlin(0.4e6, nan, 1e9, 1000.0); }, "c01");
  expect_rejected([] { mooney_rivlin(0.4e6, 0.1e6, 1e9, -1.0); }, "density");
  HyperelasticMaterial bad = kNeoHookean;
  bad.mu = 0.0;
  expect_rejected([&] { check_hyperelastic(bad); }, "mu");
  bad = kNeoHookean;
  bad.lambda = -bad.mu;  // bulk modulus λ + 2μ/3 < 0
  expect_rejected([&] { check_hyperelastic(bad); }, "lambda");
  bad = kSvk;
  bad.density = std::numeric_limits<double>::infinity();
  expect_rejected([&] { check_hyperelastic(bad); }, "density");
  for (const HyperelasticMaterial& m : kMaterials) EXPECT_NO_THROW(check_hyperelastic(m));
}

}  // namespace
}  // namespace csim
