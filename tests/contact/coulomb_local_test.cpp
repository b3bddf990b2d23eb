// The exact one-contact Coulomb solves: closed forms where they exist, and otherwise a check of the
// law itself on the result (Signorini complementarity, the friction disk, maximal dissipation).
#include "contact/coulomb_local.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

namespace csim {
namespace {

// ---- law checkers ----------------------------------------------------------------------------------

// The 2D law on u = W r + q, to a relative tolerance (impulses relative to |r|, velocities to
// max(|q|, |W r|)).
::testing::AssertionResult satisfies_law_2d(const Eigen::Matrix2d& W, const Eigen::Vector2d& q,
                                            double mu, const Eigen::Vector2d& r, double tolerance) {
  const Eigen::Vector2d u = W * r + q;
  const double impulse_scale = std::max(r.norm(), 1e-300);
  const double velocity_scale = std::max({q.norm(), (W * r).norm(), 1e-300});
  const double r_tol = tolerance * impulse_scale;
  const double u_tol = tolerance * velocity_scale;
  const auto fail = [&](const std::string& what) {
    return ::testing::AssertionFailure() << what << ": r = (" << r.transpose() << "), u = ("
                                         << u.transpose() << ")";
  };
  if (r(0) < -r_tol) return fail("negative normal impulse");
  if (u(0) < -u_tol) return fail("penetrating normal velocity");
  if (r(0) > r_tol && std::abs(u(0)) > u_tol) return fail("u_n ≠ 0 while r_n > 0");
  if (std::abs(r(1)) > mu * r(0) + r_tol) return fail("tangential impulse outside the disk");
  if (r(0) > r_tol && std::abs(u(1)) > u_tol) {
    const double sliding = u(1) > 0 ? 1.0 : -1.0;
    if (std::abs(r(1) + mu * r(0) * sliding) > r_tol) return fail("slip not at −μ r_n sign(u_t)");
  }
  return ::testing::AssertionSuccess();
}

// The 3D orthotropic law: disk (r_t1/μ1)² + (r_t2/μ2)² ≤ r_n², and in slip r_t = −r_n M² u_t/|M u_t|.
::testing::AssertionResult satisfies_law_3d(const Eigen::Matrix3d& W, const Eigen::Vector3d& q,
                                            const Eigen::Vector2d& mu, const Eigen::Vector3d& r,
                                            double tolerance) {
  const Eigen::Vector3d u = W * r + q;
  const double impulse_scale = std::max(r.norm(), 1e-300);
  const double velocity_scale = std::max({q.norm(), (W * r).norm(), 1e-300});
  const double r_tol = tolerance * impulse_scale;
  const double u_tol = tolerance * velocity_scale;
  const auto fail = [&](const std::string& what) {
    return ::testing::AssertionFailure() << what << ": r = (" << r.transpose() << "), u = ("
                                         << u.transpose() << "), mu = (" << mu.transpose() << ")";
  };
  if (r(0) < -r_tol) return fail("negative normal impulse");
  if (u(0) < -u_tol) return fail("penetrating normal velocity");
  if (r(0) > r_tol && std::abs(u(0)) > u_tol) return fail("u_n ≠ 0 while r_n > 0");
  double radius_squared = 0.0;
  for (int k = 0; k < 2; ++k) {
    if (mu(k) == 0.0) {
      if (r(k + 1) != 0.0) return fail("non-zero impulse along a frictionless axis");
    } else {
      radius_squared += (r(k + 1) / mu(k)) * (r(k + 1) / mu(k));
    }
  }
  if (std::sqrt(radius_squared) > r(0) + r_tol / std::max(mu.maxCoeff(), 1e-300))
    return fail("tangential impulse outside the elliptic disk");
  // Maximal dissipation, judged on the rough axes: M u_t ≠ 0 means sliding there.
  const Eigen::Vector2d Mu_t = mu.cwiseProduct(u.tail<2>());
  if (r(0) > r_tol && Mu_t.norm() > u_tol * mu.maxCoeff()) {
    const Eigen::Vector2d expected = -r(0) * mu.cwiseProduct(Mu_t) / Mu_t.norm();
    if ((r.tail<2>() - expected).norm() > r_tol) return fail("slip not along −M² u_t on the boundary");
  }
  return ::testing::AssertionSuccess();
}

// ---- 2D --------------------------------------------------------------------------------------------

TEST(CoulombLocal, StatusNames) {
  EXPECT_STREQ(to_string(ContactStatus::open), "open");
  EXPECT_STREQ(to_string(ContactStatus::stick), "stick");
  EXPECT_STREQ(to_string(ContactStatus::slip), "slip");
}

TEST(CoulombLocal2d, SeparatingContactIsOpen) {
  Eigen::Matrix2d W;
  W << 2.0, 0.3, 0.3, 1.0;
  Eigen::Vector2d r(7.0, 7.0);
  EXPECT_EQ(solve_local_2d(W, Eigen::Vector2d(0.5, 1.0), 0.4, r), ContactStatus::open);
  EXPECT_EQ(r, Eigen::Vector2d::Zero());
  // q_n = 0 exactly: touching without approaching needs no impulse either.
  EXPECT_EQ(solve_local_2d(W, Eigen::Vector2d(0.0, -3.0), 0.4, r), ContactStatus::open);
  EXPECT_EQ(r, Eigen::Vector2d::Zero());
}

TEST(CoulombLocal2d, SmallTangentialVelocitySticks) {
  const Eigen::Matrix2d W = Eigen::Vector2d(2.0, 3.0).asDiagonal();
  Eigen::Vector2d r;
  EXPECT_EQ(solve_local_2d(W, Eigen::Vector2d(-1.0, 0.1), 0.5, r), ContactStatus::stick);
  EXPECT_DOUBLE_EQ(r(0), 0.5);
  EXPECT_DOUBLE_EQ(r(1), -0.1 / 3.0);
  const Eigen::Vector2d u = W * r + Eigen::Vector2d(-1.0, 0.1);
  EXPECT_NEAR(u(0), 0.0, 1e-16);
  EXPECT_NEAR(u(1), 0.0, 1e-16);
}

TEST(CoulombLocal2d, SlipsOpposedToVelocityInBothDirections) {
  const Eigen::Matrix2d W = Eigen::Vector2d(2.0, 3.0).asDiagonal();
  Eigen::Vector2d r;
  // r_n = 0.5, μ r_n = 0.25; stick would need |r_t| = 2/3.
  EXPECT_EQ(solve_local_2d(W, Eigen::Vector2d(-1.0, 2.0), 0.5, r), ContactStatus::slip);
  EXPECT_DOUBLE_EQ(r(0), 0.5);
  EXPECT_DOUBLE_EQ(r(1), -0.25);
  EXPECT_DOUBLE_EQ((W * r)(1) + 2.0, 1.25);  // still sliding forward, slower

  EXPECT_EQ(solve_local_2d(W, Eigen::Vector2d(-1.0, -2.0), 0.5, r), ContactStatus::slip);
  EXPECT_DOUBLE_EQ(r(0), 0.5);
  EXPECT_DOUBLE_EQ(r(1), 0.25);
  EXPECT_DOUBLE_EQ((W * r)(1) - 2.0, -1.25);
}

TEST(CoulombLocal2d, ExactlyAtThresholdDiagonal) {
  // Stick solution r = (0.5, −0.25) lies exactly on |r_t| = μ r_n (all values exact in binary).
  const Eigen::Matrix2d W = Eigen::Vector2d(2.0, 3.0).asDiagonal();
  const Eigen::Vector2d q(-1.0, 0.75);
  Eigen::Vector2d r;
  const ContactStatus status = solve_local_2d(W, q, 0.5, r);
  EXPECT_NE(status, ContactStatus::open);
  EXPECT_TRUE(satisfies_law_2d(W, q, 0.5, r, 1e-14));
  EXPECT_NEAR(r(0), 0.5, 1e-15);
  EXPECT_NEAR(r(1), -0.25, 1e-15);
}

TEST(CoulombLocal2d, ExactlyAtThresholdCoupled) {
  // Build q from a chosen boundary impulse r* = (1, −μ) with a coupled W: q = −W r*.
  Eigen::Matrix2d W;
  W << 2.0, 0.5, 0.5, 1.0;
  const double mu = 0.4;
  const Eigen::Vector2d r_star(1.0, -mu);
  const Eigen::Vector2d q = -W * r_star;
  Eigen::Vector2d r;
  const ContactStatus status = solve_local_2d(W, q, mu, r);
  EXPECT_NE(status, ContactStatus::open);
  EXPECT_TRUE(satisfies_law_2d(W, q, mu, r, 1e-14));
  EXPECT_NEAR((r - r_star).norm(), 0.0, 1e-14);
  // Either side of the threshold, the cases are unambiguous.
  EXPECT_EQ(solve_local_2d(W, q + Eigen::Vector2d(0, -1e-3), mu, r), ContactStatus::stick);
  EXPECT_EQ(solve_local_2d(W, q + Eigen::Vector2d(0, 1e-3), mu, r), ContactStatus::slip);
}

TEST(CoulombLocal2d, CoupledDelassusSatisfiesTheLaw) {
  Eigen::Matrix2d W;
  W << 1.5, 0.4, 0.4, 0.8;
  int sticks = 0, slips = 0;
  for (const double mu : {0.05, 0.2, 0.8, 2.0}) {
    for (int i = -20; i <= 20; ++i) {
      const Eigen::Vector2d q(-1.0, 0.15 * i);
      Eigen::Vector2d r;
      const ContactStatus status = solve_local_2d(W, q, mu, r);
      ASSERT_TRUE(satisfies_law_2d(W, q, mu, r, 1e-14)) << "mu = " << mu << ", q_t = " << q(1);
      const Eigen::Vector2d u = W * r + q;
      ASSERT_GT(r(0), 0.0);
      EXPECT_NEAR(u(0), 0.0, 1e-14);
      if (status == ContactStatus::stick) {
        ++sticks;
        EXPECT_NEAR(u(1), 0.0, 1e-14);
        EXPECT_LE(std::abs(r(1)), mu * r(0));
      } else {
        ASSERT_EQ(status, ContactStatus::slip);
        ++slips;
        EXPECT_GT(std::abs(u(1)), 0.0);
        EXPECT_NEAR(r(1), -mu * r(0) * (u(1) > 0 ? 1.0 : -1.0), 1e-15 * r.norm());
      }
    }
  }
  EXPECT_GT(sticks, 20);
  EXPECT_GT(slips, 20);
}

TEST(CoulombLocal2d, FrictionlessIgnoresTangentialCoupling) {
  Eigen::Matrix2d W;
  W << 2.0, 0.7, 0.7, 1.0;
  Eigen::Vector2d r;
  EXPECT_EQ(solve_local_2d(W, Eigen::Vector2d(-3.0, 5.0), 0.0, r), ContactStatus::slip);
  EXPECT_EQ(r(0), 1.5);
  EXPECT_EQ(r(1), 0.0);
  EXPECT_EQ(solve_local_2d(W, Eigen::Vector2d(3.0, 5.0), 0.0, r), ContactStatus::open);
  EXPECT_EQ(r, Eigen::Vector2d::Zero());
}

TEST(CoulombLocal2d, LargeFrictionSticks) {
  Eigen::Matrix2d W;
  W << 2.0, 0.7, 0.7, 1.0;
  const Eigen::Vector2d q(-1.0, 50.0);
  Eigen::Vector2d r;
  EXPECT_EQ(solve_local_2d(W, q, 1e6, r), ContactStatus::stick);
  EXPECT_NEAR((W * r + q).norm(), 0.0, 1e-13);
}

TEST(CoulombLocal2d, ImmobileNormalIsOpen) {
  Eigen::Vector2d r(1.0, 1.0);
  EXPECT_EQ(solve_local_2d(Eigen::Vector2d(0.0, 1.0).asDiagonal(), Eigen::Vector2d(-1.0, 0.3), 0.5, r),
            ContactStatus::open);
  EXPECT_EQ(r, Eigen::Vector2d::Zero());
  EXPECT_EQ(solve_local_2d(Eigen::Vector2d(-1.0, 1.0).asDiagonal(), Eigen::Vector2d(-1.0, 0.3), 0.5, r),
            ContactStatus::open);
  EXPECT_EQ(r, Eigen::Vector2d::Zero());
  EXPECT_EQ(solve_local_2d(Eigen::Vector2d(1e-300, 1.0).asDiagonal(), Eigen::Vector2d(-1.0, 0.3), 0.5, r),
            ContactStatus::open);
  EXPECT_EQ(r, Eigen::Vector2d::Zero());
}

TEST(CoulombLocal2d, NonFiniteDataGiveNonFiniteImpulse) {
  Eigen::Vector2d r;
  solve_local_2d(Eigen::Matrix2d::Identity(), Eigen::Vector2d(-1.0, std::nan("")), 0.5, r);
  EXPECT_FALSE(r.allFinite());
}

// ---- 3D --------------------------------------------------------------------------------------------

TEST(CoulombLocal3d, IsotropicDiagonalMatchesClosedForm) {
  // Point-mass-like W = diag(w_n, w_t, w_t): r_n = −q_n/w_n; stick r_t = −q_t/w_t if |q_t| ≤ μ r_n w_t,
  // else slip r_t = −μ r_n q_t/|q_t| (the sliding direction does not turn).
  const double w_n = 0.5, w_t = 0.8, mu = 0.3;
  const Eigen::Matrix3d W = Eigen::Vector3d(w_n, w_t, w_t).asDiagonal();
  const double q_n = -0.2;
  const double r_n = -q_n / w_n;  // 0.4; threshold |q_t| = μ r_n w_t = 0.096
  for (const double speed : {0.01, 0.05, 0.2, 1.0, 30.0}) {
    for (int k = 0; k < 12; ++k) {
      const double angle = 0.1 + k * 0.5;
      const Eigen::Vector3d q(q_n, speed * std::cos(angle), speed * std::sin(angle));
      Eigen::Vector3d r;
      const ContactStatus status = solve_local_3d(W, q, Eigen::Vector2d(mu, mu), r);
      EXPECT_NEAR(r(0), r_n, 1e-16);
      if (speed <= mu * r_n * w_t) {
        EXPECT_EQ(status, ContactStatus::stick);
        EXPECT_NEAR(r(1), -q(1) / w_t, 1e-16);
        EXPECT_NEAR(r(2), -q(2) / w_t, 1e-16);
      } else {
        EXPECT_EQ(status, ContactStatus::slip);
        EXPECT_NEAR(r(1), -mu * r_n * std::cos(angle), 1e-16);
        EXPECT_NEAR(r(2), -mu * r_n * std::sin(angle), 1e-16);
      }
    }
  }
}

TEST(CoulombLocal3d, RandomSpdDelassusSatisfiesTheLaw) {
  std::mt19937 generator(20240611);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  std::uniform_real_distribution<double> friction(0.05, 1.5);
  int opens = 0, sticks = 0, slips = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::Matrix3d A;
    for (int i = 0; i < 9; ++i) A(i) = entry(generator);
    const Eigen::Matrix3d W = A * A.transpose() + 0.05 * Eigen::Matrix3d::Identity();
    Eigen::Vector3d q(entry(generator) - 0.6, 2 * entry(generator), 2 * entry(generator));
    const double mu1 = friction(generator);
    // Even trials isotropic, odd ones orthotropic.
    const Eigen::Vector2d mu =
        trial % 2 == 0 ? Eigen::Vector2d(mu1, mu1) : Eigen::Vector2d(mu1, friction(generator));
    Eigen::Vector3d r;
    const ContactStatus status = solve_local_3d(W, q, mu, r);
    ASSERT_TRUE(satisfies_law_3d(W, q, mu, r, 1e-11)) << "trial " << trial << " W =\n" << W;
    const Eigen::Vector3d u = W * r + q;
    switch (status) {
      case ContactStatus::open:
        ++opens;
        EXPECT_EQ(r, Eigen::Vector3d::Zero());
        break;
      case ContactStatus::stick:
        ++sticks;
        EXPECT_LE(u.norm(), 1e-13 * q.norm());
        break;
      case ContactStatus::slip: {
        ++slips;
        const double radius = std::hypot(r(1) / mu(0), r(2) / mu(1));
        EXPECT_NEAR(radius, r(0), 1e-14 * r(0));
        // r_t ∥ −M² u_t: zero cross product, negative dot product.
        const Eigen::Vector2d M2u_t = mu.cwiseProduct(mu).cwiseProduct(u.tail<2>());
        EXPECT_NEAR(r(1) * M2u_t(1) - r(2) * M2u_t(0), 0.0, 1e-12 * r.norm() * M2u_t.norm());
        EXPECT_LT(r.tail<2>().dot(M2u_t), 0.0);
        break;
      }
    }
  }
  // The sample must exercise every case, or the checks above prove little.
  EXPECT_GT(opens, 10);
  EXPECT_GT(sticks, 10);
  EXPECT_GT(slips, 50);
}

// The solve from a start (a Gauss–Seidel contact's previous impulse): the same law whatever the start,
// on Delassus blocks with a strong normal–tangential coupling (W_nt up to 0.9 √(W_nn W_tt), where
// Newton from the first guess alone can cycle between two directions), and a start that is the
// solution comes back unchanged to the bit (what a settled contact of pgs_local.h relies on).
TEST(CoulombLocal3d, SolveFromAStartSatisfiesTheLawAndKeepsASolution) {
  std::mt19937 generator(20261207);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  std::uniform_real_distribution<double> friction(0.05, 1.5);
  int slips = 0;
  for (int trial = 0; trial < 400; ++trial) {
    // W = L Lᵀ with a dominant first column of L's tangential rows: a strongly coupled block.
    Eigen::Matrix3d L = Eigen::Matrix3d::Zero();
    L(0, 0) = 0.2 + std::abs(entry(generator));
    L(1, 0) = 2.0 * entry(generator);
    L(2, 0) = 2.0 * entry(generator);
    L(1, 1) = 0.1 + std::abs(entry(generator));
    L(2, 1) = entry(generator);
    L(2, 2) = 0.1 + std::abs(entry(generator));
    const Eigen::Matrix3d W = L * L.transpose();
    const Eigen::Vector3d q(-std::abs(entry(generator)) - 0.1, 2 * entry(generator), 2 * entry(generator));
    // Even trials isotropic, odd ones orthotropic.
    const double mu1 = friction(generator);
    const Eigen::Vector2d mu_used = trial % 2 == 0 ? Eigen::Vector2d(mu1, mu1) : Eigen::Vector2d(mu1, friction(generator));
    Eigen::Vector3d reference;
    solve_local_3d(W, q, mu_used, reference);
    ASSERT_TRUE(satisfies_law_3d(W, q, mu_used, reference, 1e-11)) << "trial " << trial;
    // Starts: near the solution, at a quarter turn of it, and the reversed impulse.
    const double c = std::cos(1.5), s = std::sin(1.5);
    const Eigen::Vector3d turned(reference(0), c * reference(1) - s * reference(2), s * reference(1) + c * reference(2));
    for (const Eigen::Vector3d& start :
         {Eigen::Vector3d(reference * (1.0 + 1e-3)), turned, Eigen::Vector3d(reference(0), -reference(1), -reference(2))}) {
      Eigen::Vector3d r;
      solve_local_3d(W, q, mu_used, r, start);
      ASSERT_TRUE(satisfies_law_3d(W, q, mu_used, r, 1e-11)) << "trial " << trial << ", start " << start.transpose();
      // Every problem of this sample has one solution (so the start cannot pick another branch):
      // the solves agree to round-off.
      EXPECT_LE((r - reference).norm(), 1e-10 * reference.norm()) << "trial " << trial;
    }
    Eigen::Vector3d again;
    const ContactStatus status = solve_local_3d(W, q, mu_used, again, reference);
    EXPECT_EQ(again, reference) << "trial " << trial;
    slips += status == ContactStatus::slip;
  }
  EXPECT_GT(slips, 100);  // the sample exercises the slip search
}

TEST(CoulombLocal3d, AnisotropicFrictionSatisfiesTheLaw) {
  const Eigen::Vector2d mu(0.3, 0.1);
  Eigen::Matrix3d W;
  W << 1.0, 0.1, -0.05, 0.1, 0.9, 0.2, -0.05, 0.2, 0.7;
  for (int k = 0; k < 16; ++k) {
    const double angle = k * 0.4;
    const Eigen::Vector3d q(-1.0, std::cos(angle), std::sin(angle));
    Eigen::Vector3d r;
    const ContactStatus status = solve_local_3d(W, q, mu, r);
    EXPECT_EQ(status, ContactStatus::slip) << "angle " << angle;
    EXPECT_TRUE(satisfies_law_3d(W, q, mu, r, 1e-13)) << "angle " << angle;
  }
  // Diagonal W, velocity along t2 only: the ellipse's flat side gives r_t = (0, −μ2 r_n) exactly.
  const Eigen::Matrix3d W_diagonal = Eigen::Vector3d(1.0, 1.0, 1.0).asDiagonal();
  Eigen::Vector3d r;
  EXPECT_EQ(solve_local_3d(W_diagonal, Eigen::Vector3d(-1.0, 0.0, 2.0), mu, r), ContactStatus::slip);
  EXPECT_NEAR(r(0), 1.0, 1e-16);
  EXPECT_NEAR(r(1), 0.0, 1e-16);
  EXPECT_NEAR(r(2), -0.1, 1e-16);
}

TEST(CoulombLocal3d, UnidirectionalFrictionKeepsSmoothAxisFree) {
  const Eigen::Vector2d mu(0.1, 0.0);
  Eigen::Matrix3d W;
  W << 1.0, 0.1, -0.05, 0.1, 0.9, 0.2, -0.05, 0.2, 0.7;
  for (int k = 0; k < 16; ++k) {
    const double angle = k * 0.4;
    const Eigen::Vector3d q(-1.0, 0.5 * std::cos(angle), 0.5 * std::sin(angle));
    Eigen::Vector3d r;
    const ContactStatus status = solve_local_3d(W, q, mu, r);
    EXPECT_EQ(r(2), 0.0);
    EXPECT_TRUE(satisfies_law_3d(W, q, mu, r, 1e-14)) << "angle " << angle;
    const Eigen::Vector3d u = W * r + q;
    if (status == ContactStatus::slip) {
      EXPECT_NE(u(1), 0.0);
      EXPECT_NEAR(r(1), -mu(0) * r(0) * (u(1) > 0 ? 1.0 : -1.0), 1e-15);
    } else {
      EXPECT_EQ(status, ContactStatus::stick);
      EXPECT_NEAR(u(1), 0.0, 1e-15);
    }
  }
  // The other axis rough instead.
  Eigen::Vector3d r;
  solve_local_3d(W, Eigen::Vector3d(-1.0, 0.5, 0.5), Eigen::Vector2d(0.0, 0.2), r);
  EXPECT_EQ(r(1), 0.0);
  EXPECT_TRUE(satisfies_law_3d(W, Eigen::Vector3d(-1.0, 0.5, 0.5), Eigen::Vector2d(0.0, 0.2), r, 1e-14));
}

TEST(CoulombLocal3d, PointMassSlidingAt45DegreesWithFrictionAlongXOnly) {
  // Point mass m on the plane z = 0, frame (n, t1, t2) = (e_z, e_x, e_y), W = I/m. Over a step h it
  // falls at g·h and slides at speed V along (1, 1)/√2. Friction acts along x only:
  //   r_n = m g h (stops the fall), r_x = −μ1 r_n (slides forward in x), r_y = 0,
  //   u = (0, V/√2 − μ1 g h, V/√2).
  const double m = 2.0, g = 9.81, h = 0.01, V = 1.0, mu1 = 0.1;
  const Eigen::Matrix3d W = Eigen::Matrix3d::Identity() / m;
  const Eigen::Vector3d q(-g * h, V / std::sqrt(2.0), V / std::sqrt(2.0));
  Eigen::Vector3d r;
  EXPECT_EQ(solve_local_3d(W, q, Eigen::Vector2d(mu1, 0.0), r), ContactStatus::slip);
  EXPECT_NEAR(r(0), m * g * h, 1e-16);
  EXPECT_NEAR(r(1), -mu1 * m * g * h, 1e-16);
  EXPECT_EQ(r(2), 0.0);
  const Eigen::Vector3d u = W * r + q;
  EXPECT_NEAR(u(0), 0.0, 1e-16);
  EXPECT_NEAR(u(1), V / std::sqrt(2.0) - mu1 * g * h, 1e-15);
  EXPECT_EQ(u(2), V / std::sqrt(2.0));
}

TEST(CoulombLocal3d, FrictionlessAndLargeFriction) {
  Eigen::Matrix3d W;
  W << 1.0, 0.1, -0.05, 0.1, 0.9, 0.2, -0.05, 0.2, 0.7;
  const Eigen::Vector3d q(-2.0, 0.5, -0.3);
  Eigen::Vector3d r;
  EXPECT_EQ(solve_local_3d(W, q, Eigen::Vector2d::Zero(), r), ContactStatus::slip);
  EXPECT_EQ(r, Eigen::Vector3d(2.0, 0.0, 0.0));
  EXPECT_EQ(solve_local_3d(W, q, Eigen::Vector2d(1e8, 1e8), r), ContactStatus::stick);
  EXPECT_LE((W * r + q).norm(), 1e-14);
}

TEST(CoulombLocal3d, ImmobileNormalIsOpen) {
  Eigen::Vector3d r(1.0, 1.0, 1.0);
  EXPECT_EQ(solve_local_3d(Eigen::Vector3d(0.0, 1.0, 1.0).asDiagonal(), Eigen::Vector3d(-1.0, 0.1, 0.1),
                           Eigen::Vector2d(0.5, 0.5), r),
            ContactStatus::open);
  EXPECT_EQ(r, Eigen::Vector3d::Zero());
  EXPECT_EQ(solve_local_3d(Eigen::Vector3d(1e-20, 1.0, 1.0).asDiagonal(), Eigen::Vector3d(-1.0, 0.1, 0.1),
                           Eigen::Vector2d(0.5, 0.5), r),
            ContactStatus::open);
  EXPECT_EQ(r, Eigen::Vector3d::Zero());
}

TEST(CoulombLocal3d, SingularTangentialBlockStillSatisfiesTheLaw) {
  // Tangential rows that cannot move (W_tt = 0): u_t = q_t whatever r, so the contact slips at q_t.
  const Eigen::Matrix3d W = Eigen::Vector3d(1.0, 0.0, 0.0).asDiagonal();
  const Eigen::Vector3d q(-1.0, 0.3, -0.4);
  const Eigen::Vector2d mu(0.5, 0.5);
  Eigen::Vector3d r;
  EXPECT_EQ(solve_local_3d(W, q, mu, r), ContactStatus::slip);
  EXPECT_TRUE(satisfies_law_3d(W, q, mu, r, 1e-14));
  EXPECT_NEAR(r(1), -0.5 * 0.6, 1e-15);
  EXPECT_NEAR(r(2), 0.5 * 0.8, 1e-15);
}

}  // namespace
}  // namespace csim
