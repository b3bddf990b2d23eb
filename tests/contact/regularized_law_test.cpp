#include "contact/regularized_law.h"

#include <gtest/gtest.h>

#include <cmath>

namespace csim {
namespace {

RegularizedContactLaw law(double mu1, double mu2) {
  RegularizedContactLaw l;
  l.stiffness = 1e6;
  l.damping = 100.0;
  l.epsilon = 1e-3;
  l.mu << mu1, mu2;
  return l;
}

TEST(RegularizedLaw, OpenContactCarriesNothing) {
  EXPECT_EQ(regularized_contact_force(law(0.3, 0.3), 1e-6, Eigen::Vector3d(-1, 1, 0), 3).norm(), 0.0);
  EXPECT_EQ(regularized_contact_force(law(0.3, 0.3), 0.0, Eigen::Vector3d(-1, 1, 0), 3).norm(), 0.0);
}

TEST(RegularizedLaw, PenaltyWithDampingAndNoAdhesion) {
  const auto f = regularized_contact_force(law(0, 0), -1e-4, Eigen::Vector3d(-0.5, 0, 0), 3);
  EXPECT_DOUBLE_EQ(f(0), 1e6 * 1e-4 + 100 * 0.5);
  // Separating fast: the dashpot would pull, the law does not.
  EXPECT_EQ(regularized_contact_force(law(0, 0), -1e-4, Eigen::Vector3d(10, 0, 0), 3)(0), 0.0);
}

TEST(RegularizedLaw, IsotropicSlipTendsToCoulomb) {
  const auto f = regularized_contact_force(law(0.3, 0.3), -1e-4, Eigen::Vector3d(0, 3, 4), 3);
  const double normal = f(0);
  const Eigen::Vector2d expected = -0.3 * normal * Eigen::Vector2d(3, 4) / std::sqrt(25.0 + 1e-6);
  EXPECT_NEAR((f.tail<2>() - expected).norm(), 0.0, 1e-12 * normal);
  // Relative shortfall ε²/(2u²) at |u| = 5 m/s, ε = 1e-3.
  EXPECT_NEAR(1.0 - f.tail<2>().norm() / (0.3 * normal), 0.5 * 1e-6 / 25.0, 1e-12);
}

TEST(RegularizedLaw, CreepVelocityAtAGivenLoadRatio) {
  // At |u| = ε ρ/√(1−ρ²) the friction force is ρ μ F_n.
  const double rho = 0.5, epsilon = 1e-3;
  const double creep = epsilon * rho / std::sqrt(1 - rho * rho);
  const auto f = regularized_contact_force(law(0.3, 0.3), -1e-4, Eigen::Vector3d(0, creep, 0), 2);
  EXPECT_NEAR(-f(1) / (0.3 * f(0)), rho, 1e-12);
  EXPECT_EQ(f(2), 0.0);
}

TEST(RegularizedLaw, UnidirectionalFrictionActsAlongT1Only) {
  const auto f = regularized_contact_force(law(0.1, 0.0), -1e-4, Eigen::Vector3d(0, 2, 7), 3);
  EXPECT_EQ(f(2), 0.0);
  EXPECT_NEAR(f(1), -0.1 * f(0) * 2 / std::sqrt(4 + 1e-6), 1e-12 * f(0));
}

TEST(RegularizedLaw, AnisotropicSlipIsOnTheEllipseAndMaximallyDissipative) {
  const auto f = regularized_contact_force(law(0.3, 0.1), -1e-4, Eigen::Vector3d(0, 50, -20), 3);
  const Eigen::Vector2d ft = f.tail<2>();
  // On the ellipse (F1/μ1)² + (F2/μ2)² = F_n² (up to the ε shortfall).
  EXPECT_NEAR(std::hypot(ft(0) / 0.3, ft(1) / 0.1), f(0), 1e-6 * f(0));
  // Opposite to M² u: F_t ∥ −(μ1² u1, μ2² u2).
  const Eigen::Vector2d direction(-0.09 * 50, -0.01 * -20);
  EXPECT_NEAR(ft.normalized().dot(direction.normalized()), 1.0, 1e-12);
}

TEST(RegularizedLaw, DampingRatioReproducesTheRestitution) {
  EXPECT_EQ(damping_ratio_for_restitution(1.0), 0.0);
  EXPECT_EQ(damping_ratio_for_restitution(0.0), 1.0);
  for (double e : {0.1, 0.5, 0.9}) {
    const double zeta = damping_ratio_for_restitution(e);
    EXPECT_NEAR(std::exp(-zeta * M_PI / std::sqrt(1 - zeta * zeta)), e, 1e-14);
  }
}

}  // namespace
}  // namespace csim
