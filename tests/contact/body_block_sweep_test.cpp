// The sparse path of PgsSolver with W given by its body-block factors (friction_contact_problem.h,
// BodyBlockDelassus; sparse_pgs.h): the sweeps apply W through the bodies' scaled velocities instead of
// W's block rows, and must give the impulses of the assembled W's sweeps to round-off.
#include "contact/pgs_solver.h"
#include "contact/sparse_pgs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace csim {
namespace {

constexpr double kRadius = 0.1;     // m
constexpr double kMass = 1.0;       // kg
constexpr double kStep = 1e-3;      // s
constexpr double kGravity = 9.81;   // m/s²

struct Pile {
  FrictionContactProblem assembled;  // W_sparse = H M⁻¹ Hᵀ, formed dense then stored by blocks
  FrictionContactProblem by_bodies;  // the same, with the body-block factors K = H M^(-1/2)
};

// Eight spheres in a 2 × 2 × 2 cube, each touching its three neighbours, the lower four on the ground:
// 12 sphere–sphere and 4 ground contacts, 48 rows for 48 freedoms. Free velocities: one step of gravity
// and a deterministic spread of lateral velocities and spins, so that some contacts stick and some slip.
Pile cube_of_spheres() {
  const int bodies = 8;
  std::vector<Eigen::Vector3d> centre;
  for (int k = 0; k < bodies; ++k)
    centre.emplace_back((k & 1 ? 1 : -1) * kRadius, (k & 2 ? 1 : -1) * kRadius, kRadius + (k & 4 ? 2 * kRadius : 0.0));
  struct Contact {
    int A, B;  // u = v_B − v_A at the contact point; A = −1: the ground
    Eigen::Vector3d n;
  };
  std::vector<Contact> contacts;
  for (int a = 0; a < bodies; ++a) {
    if (!(a & 4)) contacts.push_back({-1, a, Eigen::Vector3d::UnitZ()});
    for (int b = a + 1; b < bodies; ++b)
      if (std::abs((centre[b] - centre[a]).norm() - 2 * kRadius) < 1e-12)
        contacts.push_back({a, b, (centre[b] - centre[a]).normalized()});
  }
  const int nc = static_cast<int>(contacts.size()), m = 3 * nc, n = 6 * bodies;
  Eigen::VectorXd inverse_mass(n), v(n);
  for (int k = 0; k < bodies; ++k) {
    inverse_mass.segment<3>(6 * k).setConstant(1 / kMass);
    inverse_mass.segment<3>(6 * k + 3).setConstant(1 / (0.4 * kMass * kRadius * kRadius));
    v.segment<6>(6 * k) << 0.05 * std::sin(k + 1.0), 0.05 * std::cos(2.0 * k), -kGravity * kStep,
        3.0 * std::sin(3.0 * k), 2.0 * std::cos(k + 0.5), 1.0 * std::sin(5.0 * k);
  }
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(m, n);
  for (int c = 0; c < nc; ++c) {
    const Eigen::Vector3d& normal = contacts[c].n;
    const Eigen::Vector3d t1 = normal.unitOrthogonal(), t2 = normal.cross(t1);
    const Eigen::Vector3d directions[3] = {normal, t1, t2};
    for (int j = 0; j < 3; ++j) {
      const Eigen::Vector3d& d = directions[j];
      // The point of B at −R n from its centre, of A at +R n: [dᵀ, (p × d)ᵀ] each.
      H.block<1, 3>(3 * c + j, 6 * contacts[c].B) += d.transpose();
      H.block<1, 3>(3 * c + j, 6 * contacts[c].B + 3) += (-kRadius * normal).cross(d).transpose();
      if (contacts[c].A >= 0) {
        H.block<1, 3>(3 * c + j, 6 * contacts[c].A) -= d.transpose();
        H.block<1, 3>(3 * c + j, 6 * contacts[c].A + 3) -= (kRadius * normal).cross(d).transpose();
      }
    }
  }
  Pile pile;
  FrictionContactProblem& problem = pile.assembled;
  problem.dimension = 3;
  problem.contacts = nc;
  problem.storage = DelassusStorage::sparse;
  problem.W_sparse = block_sparse(H * inverse_mass.asDiagonal() * H.transpose(), 3);
  problem.b = H * v;
  problem.mu.assign(nc, Eigen::Vector2d(0.5, 0.5));
  pile.by_bodies = problem;
  BodyBlockDelassus& blocks = pile.by_bodies.body_blocks;
  const int kBody = BodyBlockDelassus::kBodySize;
  blocks.bodies = bodies;
  blocks.scaled_rows.assign(static_cast<std::size_t>(2 * nc * 3 * kBody), 0.0);
  for (int c = 0; c < nc; ++c) {
    // Bodies ascending: the ground (−1) on side 1.
    const int first = contacts[c].A >= 0 ? contacts[c].A : contacts[c].B;
    const int second = contacts[c].A >= 0 ? contacts[c].B : -1;
    blocks.body.push_back({first, second});
    for (int side = 0; side < 2; ++side) {
      const int b = side == 0 ? first : second;
      if (b < 0) continue;
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < kBody; ++k)
          blocks.scaled_rows[(static_cast<std::size_t>(2 * c + side) * 3 + i) * kBody + k] =
              H(3 * c + i, 6 * b + k) * std::sqrt(inverse_mass(6 * b + k));
    }
  }
  return pile;
}

// A fixed number of sweeps, neither relaxed nor polished: the same iterates whichever way W is applied.
TEST(BodyBlockSweep, GivesTheAssembledSweepsImpulsesToRoundOff) {
  const Pile pile = cube_of_spheres();
  for (const int sweeps : {1, 5, 40}) {
    PgsParameters parameters;
    parameters.max_iterations = sweeps;
    parameters.tolerance = 1e-300;  // never met: every sweep runs
    parameters.polish = false;
    parameters.relax_sparse = false;
    Eigen::VectorXd r_assembled, r_by_bodies;
    const PgsStatistics assembled = PgsSolver(parameters).solve(pile.assembled, r_assembled);
    const PgsStatistics by_bodies = PgsSolver(parameters).solve(pile.by_bodies, r_by_bodies);
    ASSERT_GT(r_assembled.norm(), 0.0);
    EXPECT_EQ(assembled.iterations, by_bodies.iterations);
    EXPECT_LE((r_assembled - r_by_bodies).norm(), 1e-12 * r_assembled.norm()) << sweeps << " sweeps";
    // The residual is relative to the velocity scale (pgs_solver.h): the two agree to round-off of it.
    EXPECT_NEAR(assembled.residual, by_bodies.residual, 1e-12) << sweeps << " sweeps";
  }
}

// The solver's defaults (the relaxed attempt first, the polish on schedule): both converge, to impulses
// within the tolerance's reach of each other, and the reported residual is the assembled W's.
TEST(BodyBlockSweep, ConvergesAsTheAssembledPath) {
  const Pile pile = cube_of_spheres();
  PgsParameters parameters;
  parameters.tolerance = 1e-10;
  Eigen::VectorXd r_assembled, r_by_bodies;
  const PgsStatistics assembled = PgsSolver(parameters).solve(pile.assembled, r_assembled);
  const PgsStatistics by_bodies = PgsSolver(parameters).solve(pile.by_bodies, r_by_bodies);
  ASSERT_TRUE(assembled.converged);
  ASSERT_TRUE(by_bodies.converged) << by_bodies.residual;
  EXPECT_LE(PgsSolver::residual(pile.assembled, r_by_bodies), 1e-10);
  EXPECT_NEAR(by_bodies.residual, PgsSolver::residual(pile.assembled, r_by_bodies), 1e-12);
  EXPECT_EQ(assembled.iterations, by_bodies.iterations);
}

// Factors that do not match the problem are refused, naming what is wrong.
TEST(BodyBlockSweep, RefusesFactorsOfAnotherSize) {
  Pile pile = cube_of_spheres();
  pile.by_bodies.body_blocks.body.pop_back();
  Eigen::VectorXd r;
  EXPECT_THROW(PgsSolver().solve(pile.by_bodies, r), std::invalid_argument);
}

}  // namespace
}  // namespace csim
