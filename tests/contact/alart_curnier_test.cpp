// The semismooth Newton method on the Alart–Curnier equations: closed-form single contacts, and the
// ill-conditioned problems met in scenes that Gauss–Seidel alone does not finish.
#include "contact/alart_curnier.h"
#include "contact/pgs_solver.h"
#include "tests/contact/test_problems.h"

#include <gtest/gtest.h>


namespace csim {
namespace {

FrictionContactProblem single_contact_3d(const Eigen::Vector3d& q, double mu) {
  FrictionContactProblem problem;
  problem.dimension = 3;
  problem.contacts = 1;
  problem.mu = {Eigen::Vector2d(mu, mu)};
  problem.W = Eigen::Matrix3d::Identity();
  problem.b = q;
  return problem;
}

TEST(AlartCurnier, SingleContactSlipsAgainstItsVelocity) {
  // W = I: r_n = −q_n = 1; the free tangential velocity (2, 0) exceeds μ r_n, so r_t = −μ r_n (1, 0)
  // and u_t = (2 − 0.3, 0), along the free velocity.
  const FrictionContactProblem problem = single_contact_3d(Eigen::Vector3d(-1, 2, 0), 0.3);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(3);
  NewtonStatistics statistics;
  ASSERT_TRUE(alart_curnier_newton(problem, r, 20, 1e-14, &statistics));
  EXPECT_NEAR(r(0), 1.0, 1e-13);
  EXPECT_NEAR(r(1), -0.3, 1e-13);
  EXPECT_NEAR(r(2), 0.0, 1e-13);
  EXPECT_LE(statistics.iterations, 10);
  EXPECT_LE(PgsSolver::residual(problem, r), 1e-13);
}

TEST(AlartCurnier, SingleContactSticksAndOpens) {
  FrictionContactProblem problem = single_contact_3d(Eigen::Vector3d(-1, 0.1, -0.2), 0.3);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(3);
  ASSERT_TRUE(alart_curnier_newton(problem, r, 20, 1e-14));
  EXPECT_TRUE(r.isApprox(Eigen::Vector3d(1, -0.1, 0.2), 1e-13));  // stick: u = 0
  problem.b = Eigen::Vector3d(0.5, 1, 1);                           // separating
  r = Eigen::Vector3d(1, 0.2, 0.2);
  ASSERT_TRUE(alart_curnier_newton(problem, r, 20, 1e-14));
  EXPECT_LE(r.norm(), 1e-13);
}

TEST(AlartCurnier, OrthotropicFrictionIsLeftToGaussSeidel) {
  FrictionContactProblem problem = single_contact_3d(Eigen::Vector3d(-1, 2, 0), 0.3);
  problem.mu[0] = Eigen::Vector2d(0.3, 0.1);
  Eigen::VectorXd r = Eigen::Vector3d(0.5, 0.0, 0.0);
  EXPECT_FALSE(alart_curnier_newton(problem, r, 20, 1e-14));
  EXPECT_EQ(r, Eigen::VectorXd(Eigen::Vector3d(0.5, 0.0, 0.0)));
}

TEST(AlartCurnier, FinishesTheBoxOnFourVerticesOfAStiffBlock) {
  // Met in scenes/box-on-block-3d (push 0.9 mu m g) at its landing: a rigid box on four vertices of a
  // stiff elastic block, W with eigenvalues from 3e-5 to 1.3. Gauss–Seidel alone stays near 1e-6
  // after 2000 sweeps (the run then failed); with the polish (active set, then Newton, which finds
  // the slip directions in 3D) the solver converges to 1e-12.
  const FrictionContactProblem problem = test::problem_file("box_on_four_vertices_3d.txt");
  PgsParameters plain;
  plain.polish = false;
  plain.tolerance = 1e-12;
  Eigen::VectorXd r_plain;
  const PgsStatistics gauss_seidel = PgsSolver(plain).solve(problem, r_plain);
  EXPECT_FALSE(gauss_seidel.converged);
  EXPECT_GT(gauss_seidel.residual, 1e-8);
  PgsParameters polished = plain;
  polished.polish = true;
  Eigen::VectorXd r;
  const PgsStatistics with_polish = PgsSolver(polished).solve(problem, r);
  EXPECT_TRUE(with_polish.converged) << with_polish.residual;
  EXPECT_LE(with_polish.iterations, 200);
  // Newton alone from zero reaches the same solution with ρ scaled by 1e3, and stalls at scale 1.
  Eigen::VectorXd r_newton = Eigen::VectorXd::Zero(problem.size());
  NewtonStatistics statistics;
  ASSERT_TRUE(alart_curnier_newton(problem, r_newton, 50, 1e-14, &statistics, 1e3));
  EXPECT_LE(statistics.iterations, 15);
  EXPECT_LE(PgsSolver::residual(problem, r_newton), 1e-12) << statistics.iterations;
  EXPECT_LE((r_newton - r).norm(), 1e-8 * r.norm());
  Eigen::VectorXd r_unscaled = Eigen::VectorXd::Zero(problem.size());
  ASSERT_TRUE(alart_curnier_newton(problem, r_unscaled, 20, 1e-14));
  EXPECT_GT(PgsSolver::residual(problem, r_unscaled), 1e-7);
}

TEST(AlartCurnier, ADirectionNoImpulseReachesLeavesTheOthersExact) {
  // Two pressed, sticking 3D contacts; the first one's second tangent has an empty row and column
  // of W (a node held in that direction, as a 3D ring's nodes axially), and a free velocity there
  // that no impulse can cancel. Newton's matrix is then singular: the other five components must
  // still reach their exact sticking solution, W_kk r_k = −q_k, and the unreachable one keep its
  // value.
  FrictionContactProblem problem;
  problem.dimension = 3;
  problem.contacts = 2;
  problem.mu = {Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(1.0, 1.0)};
  const std::vector<Eigen::Index> kept = {0, 1, 3, 4, 5};
  Eigen::MatrixXd A(5, 5);
  A << 2.0, 0.3, 0.5, -0.2, 0.1,  //
      0.3, 1.5, 0.1, 0.4, -0.3,   //
      0.5, 0.1, 2.5, 0.2, 0.3,    //
      -0.2, 0.4, 0.2, 1.8, 0.1,   //
      0.1, -0.3, 0.3, 0.1, 1.2;
  problem.W = Eigen::MatrixXd::Zero(6, 6);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) problem.W(kept[i], kept[j]) = A(i, j);
  // The sticking solution, pressed and inside both cones, and the free velocity that gives it.
  Eigen::VectorXd exact(5);
  exact << 1.0, 0.1, 0.8, -0.1, 0.15;
  const Eigen::VectorXd q_kept = -A * exact;
  problem.b = Eigen::VectorXd::Zero(6);
  for (int i = 0; i < 5; ++i) problem.b(kept[i]) = q_kept(i);
  problem.b(2) = 1e-6;

  Eigen::VectorXd r = Eigen::VectorXd::Zero(6);
  r(2) = 0.01;
  NewtonStatistics statistics;
  ASSERT_TRUE(alart_curnier_newton(problem, r, 20, 1e-14, &statistics));
  EXPECT_EQ(r(2), 0.01);
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(r(kept[i]), exact(i), 1e-13) << "component " << kept[i];
  EXPECT_LE(statistics.iterations, 5);
}

}  // namespace
}  // namespace csim
