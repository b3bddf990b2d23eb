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

// The tangent against central differences of the force, in 2D and 3D, isotropic and orthotropic, in
// slip and near stick (|u_t| ~ ε), with damping on.
TEST(RegularizedLaw, TangentMatchesDifferencesOfTheForce) {
  struct Case {
    double mu1, mu2, gap;
    Eigen::Vector3d u;
    int dimension;
  };
  const Case cases[] = {{0.3, 0.3, -1e-4, {-0.01, 2e-3, -1e-3}, 3}, {0.5, 0.2, -2e-4, {0.01, 5e-4, 3e-4}, 3},
                        {0.3, 0.3, -1e-4, {-0.01, 1e-3, 0.0}, 2},   {0.4, 0.0, -3e-5, {0.0, -2e-3, 1e-3}, 3}};
  for (const Case& c : cases) {
    const RegularizedContactLaw l = law(c.mu1, c.mu2);
    Eigen::Vector3d d_gap;
    Eigen::Matrix3d d_velocity;
    regularized_contact_tangent(l, c.gap, c.u, c.dimension, d_gap, d_velocity);
    const double dg = 1e-10, du = 1e-8;
    const Eigen::Vector3d fd_gap = (regularized_contact_force(l, c.gap + dg, c.u, c.dimension) -
                                    regularized_contact_force(l, c.gap - dg, c.u, c.dimension)) / (2 * dg);
    EXPECT_LT((fd_gap - d_gap).norm(), 1e-6 * d_gap.norm());
    for (int j = 0; j < c.dimension; ++j) {
      Eigen::Vector3d plus = c.u, minus = c.u;
      plus(j) += du;
      minus(j) -= du;
      const Eigen::Vector3d fd = (regularized_contact_force(l, c.gap, plus, c.dimension) -
                                  regularized_contact_force(l, c.gap, minus, c.dimension)) / (2 * du);
      EXPECT_LT((fd - d_velocity.col(j)).norm(), 1e-5 * d_velocity.norm()) << "column " << j;
    }
  }
  // Open: nothing.
  Eigen::Vector3d d_gap;
  Eigen::Matrix3d d_velocity;
  regularized_contact_tangent(law(0.3, 0.3), 1e-6, Eigen::Vector3d::Zero(), 3, d_gap, d_velocity);
  EXPECT_EQ(d_gap.norm() + d_velocity.norm(), 0.0);
}

}  // namespace
}  // namespace csim
