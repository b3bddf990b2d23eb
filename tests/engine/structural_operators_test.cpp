// StructuralOperators on its own: M, K and the factored iteration matrix A = M + hθC + h²θ²K of one
// spring element between two point masses, against the hand-written matrices; and the sparse path
// (an FE body), against the dense matrices of Dynamics.
#include "engine/structural_operators.h"
#include "engine/bodies/fe_body.h"
#include "engine/bodies/rigid_body_2d.h"
#include "engine/dynamics.h"
#include "fem/mesh_generators.h"
#include "tests/engine/test_worlds.h"
#include "tools/scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace csim {
namespace {

// Two point masses in the plane (2 kg at the origin, 3 kg at (1, 0)) joined by an isotropic spring
// of k = 100 N/m: M = diag(2, 2, 3, 3), K = k [[I, −I], [−I, I]] (world.h: force on A = −k d).
World two_masses() {
  World world;
  world.dimension = 2;
  world.bodies.push_back(test::point_mass("a", 2, 2.0, Eigen::Vector3d::Zero()));
  world.bodies.push_back(test::point_mass("b", 2, 3.0, Eigen::Vector3d(1.0, 0.0, 0.0)));
  Spring spring;
  spring.body_a = 0;
  spring.body_b = 1;
  spring.stiffness = 100.0;
  world.springs.push_back(spring);
  world.finalize_layout();
  return world;
}

Matrix hand_mass() { return Eigen::Vector4d(2.0, 2.0, 3.0, 3.0).asDiagonal(); }

Matrix hand_stiffness() {
  Matrix K = Matrix::Zero(4, 4);
  const Matrix identity = Matrix::Identity(2, 2);
  K.block(0, 0, 2, 2) = identity;
  K.block(2, 2, 2, 2) = identity;
  K.block(0, 2, 2, 2) = -identity;
  K.block(2, 0, 2, 2) = -identity;
  return 100.0 * K;
}

TEST(StructuralOperators, MassAndStiffnessOfASpringElementAreTheHandMatrices) {
  const World world = two_masses();
  const Dynamics dynamics(world);
  StructuralOperators operators(dynamics);
  const State state = test::start(world);
  operators.update(state.q, 1e-2, 0.5);
  EXPECT_TRUE(operators.has_stiffness());
  EXPECT_FALSE(operators.has_damping());
  EXPECT_FALSE(operators.nonlinear());
  Vector column;
  for (int j = 0; j < 4; ++j) {
    const Vector e = Vector::Unit(4, j);
    operators.apply_mass(e, column);
    EXPECT_LT((column - hand_mass().col(j)).norm(), 1e-14) << "column " << j << " of M";
    operators.apply_stiffness(e, column);
    EXPECT_LT((column - hand_stiffness().col(j)).norm(), 1e-12) << "column " << j << " of K";
  }
}

TEST(StructuralOperators, SolvesWithTheIterationMatrix) {
  const World world = two_masses();
  const Dynamics dynamics(world);
  StructuralOperators operators(dynamics);
  const State state = test::start(world);
  const double h = 1e-2, theta = 0.7;
  operators.update(state.q, h, theta);
  const Matrix A = hand_mass() + (h * h * theta * theta) * hand_stiffness();
  const Vector x = Eigen::Vector4d(1.0, -2.0, 0.5, 3.0);
  Vector solved = x;
  operators.solve_in_place(solved);
  EXPECT_LT((A * solved - x).norm(), 1e-13 * x.norm());
  EXPECT_EQ(operators.factorizations(), 1);
  EXPECT_EQ(operators.regularizations(), 0);
  // K is constant (a spring between translating points): the same h keeps the factorization.
  operators.update(state.q, h, theta);
  EXPECT_EQ(operators.factorizations(), 1);
}

// A 6 × 6 quad4 square (1 m, consistent mass, Rayleigh damping, its left side held: 84 unknowns, above
// kDenseLimit) and a 1 kg point mass at (2, 1) tied to its top right corner by a spring: M, C and K
// overlap in every pattern the sparse path sums.
World elastic_square_and_mass() {
  World world;
  world.dimension = 2;
  const Mesh mesh = rectangle_mesh(1.0, 1.0, 6, 6, ElementType::quad4);
  std::vector<std::pair<int, int>> fixed;
  for (int node : mesh.node_sets.at("left"))
    for (int c = 0; c < 2; ++c) fixed.emplace_back(node, c);
  BodyInstance square;
  square.name = "square";
  square.body = std::make_unique<FeBody>(mesh, ElasticMaterial{2e5, 0.3, 1000.0}, 0.1, false, fixed, 2.0, 1e-3);
  const int n = square.body->position_size();
  square.reference_position = square.initial_position = square.initial_velocity = Vector::Zero(n);
  world.bodies.push_back(std::move(square));
  world.bodies.push_back(test::point_mass("mass", 2, 1.0, Eigen::Vector3d(2.0, 1.0, 0.0)));
  Spring spring;
  spring.body_a = 0;
  spring.point_a = Eigen::Vector3d(1.0, 1.0, 0.0);
  spring.body_b = 1;
  spring.stiffness = 5e4;
  world.springs.push_back(spring);
  world.finalize_layout();
  return world;
}

// The sparse operators keep one copy of K (the bodies' and the springs' summed once, the bodies' own
// then dropped) and A's lower triangle only: M v, C v, K v and A⁻¹ b must still be those of the
// full matrices, also after a new h refactors A from the kept sum.
TEST(StructuralOperators, SparseOperatorsAreTheAssembledMatrices) {
  const World world = elastic_square_and_mass();
  const Dynamics dynamics(world);
  StructuralOperators operators(dynamics);
  const State state = test::start(world);
  const int n = world.velocity_size;
  ASSERT_GT(n, StructuralOperators::kDenseLimit);
  const Matrix M(dynamics.mass()), C(dynamics.damping());
  Matrix K;
  dynamics.spring_stiffness(state.q, K);
  K += Matrix(dynamics.body_stiffness());
  ASSERT_GT(C.norm(), 0.0);
  const double theta = 0.55;
  const Vector b = Vector::LinSpaced(n, -1.0, 2.0);
  for (double h : {1e-2, 3e-3}) {
    operators.update(state.q, h, theta);
    EXPECT_TRUE(operators.sparse());
    EXPECT_TRUE(operators.has_damping());
    Vector column;
    for (int j = 0; j < n; ++j) {
      const Vector e = Vector::Unit(n, j);
      operators.apply_mass(e, column);
      EXPECT_LE((column - M.col(j)).norm(), 1e-14 * M.norm()) << "column " << j << " of M";
      operators.apply_damping(e, column);
      EXPECT_LE((column - C.col(j)).norm(), 1e-14 * C.norm()) << "column " << j << " of C";
      operators.apply_stiffness(e, column);
      EXPECT_LE((column - K.col(j)).norm(), 1e-14 * K.norm()) << "column " << j << " of K";
    }
    const Matrix A = M + (h * theta) * C + (h * h * theta * theta) * K;
    Vector solved = b;
    operators.solve_in_place(solved);
    EXPECT_LT((A * solved - b).norm(), 1e-12 * b.norm()) << "h = " << h;
  }
  EXPECT_EQ(operators.factorizations(), 2);
}

// A plane rigid body (q = x, y, φ) held by a spring at the corner (0.5, 0.5): K depends on φ alone.
World turning_body() {
  World world;
  world.dimension = 2;
  BodyInstance b;
  b.name = "shoe";
  b.body = std::make_unique<RigidBody2d>(7.0, 0.5);
  b.reference_position = Eigen::Vector3d::Zero();
  b.initial_position = b.reference_position;
  b.initial_velocity = Eigen::Vector3d::Zero();
  world.bodies.push_back(std::move(b));
  Spring spring;
  spring.body_a = 0;
  spring.point_a = Eigen::Vector3d(0.5, 0.5, 0.0);
  spring.stiffness = 1e4;
  world.springs.push_back(spring);
  world.finalize_layout();
  return world;
}

// The factorization is kept while the spring's orientation coordinate (or K, to the bit), h and θ are the same, and is
// redone when any of them changes, A then being the one a fresh factorization gives.
TEST(StructuralOperators, RefactorsWhenTheStiffnessOrTheStepChanges) {
  const World world = turning_body();
  const Dynamics dynamics(world);
  EXPECT_EQ(dynamics.spring_stiffness_coordinates(), std::vector<int>{2});
  StructuralOperators operators(dynamics);
  Vector q = Eigen::Vector3d(0.0, 0.0, 0.0);
  const double h = 1e-2, theta = 0.5;
  operators.update(q, h, theta);
  EXPECT_EQ(operators.factorizations(), 1);
  q.head<2>() << 0.3, -0.2;  // a translation leaves K as it is
  operators.update(q, h, theta);
  EXPECT_EQ(operators.factorizations(), 1);
  auto agrees_with_fresh = [&](const Vector& at, double step, double weight) {
    StructuralOperators fresh(dynamics);
    fresh.update(at, step, weight);
    Vector x = Eigen::Vector3d(1.0, -2.0, 0.5), y = x;
    operators.solve_in_place(x);
    fresh.solve_in_place(y);
    return x == y;
  };
  q(2) = 1e-25;  // a turn by round-off leaves K the same to the bit: A is kept
  operators.update(q, h, theta);
  EXPECT_EQ(operators.factorizations(), 1);
  EXPECT_TRUE(agrees_with_fresh(q, h, theta));
  q(2) = 0.1;  // a turn changes K
  operators.update(q, h, theta);
  EXPECT_EQ(operators.factorizations(), 2);
  EXPECT_TRUE(agrees_with_fresh(q, h, theta));
  operators.update(q, 2 * h, theta);  // so does a new step
  EXPECT_EQ(operators.factorizations(), 3);
  EXPECT_TRUE(agrees_with_fresh(q, 2 * h, theta));
  operators.update(q, 2 * h, 0.7);  // and a new θ
  EXPECT_EQ(operators.factorizations(), 4);
  EXPECT_TRUE(agrees_with_fresh(q, 2 * h, 0.7));
}

}  // namespace
}  // namespace csim

namespace csim {
namespace {

// A lumped World's diagonal M gives Dynamics' kinetic energy to the bit through its diagonal (Moreau–
// Jean's energy balance takes it a step), signed zeros and tiny products included; a World whose M
// is not diagonal (an FE body) takes Dynamics' own, with M x in the same pass. M x beside it is
// apply_mass's to the bit; the energy alone (a θ = ½ step's) is the same.
TEST(StructuralOperators, KineticEnergyIsDynamicsToTheBit) {
  World plane_body;
  plane_body.dimension = 2;
  {
    BodyInstance b;
    b.name = "shoe";
    b.body = std::make_unique<RigidBody2d>(7000.0, 7000.0 / 6.0);
    b.initial_position = b.reference_position = b.initial_velocity = Vector::Zero(3);
    plane_body.bodies.push_back(std::move(b));
  }
  plane_body.finalize_layout();
  const World points = two_masses();
  const auto cube = load_scene(CSIM_SOURCE_DIR "/scenes/incline-3d/scene.yaml", {});
  const auto pad = load_scene(CSIM_SOURCE_DIR "/scenes/sdnd100-a/scene.yaml", {});
  const auto plate = load_scene(CSIM_SOURCE_DIR "/scenes/sdnv104-quad4/scene.yaml", {});
  for (const World* world : std::initializer_list<const World*>{&plane_body, &points, &cube->world, &pad->world, &plate->world}) {
    const Dynamics dynamics(*world);
    const StructuralOperators operators(dynamics);
    Vector v(world->velocity_size), x(world->velocity_size), Mx, expected_Mx;
    for (int trial = 0; trial < 200; ++trial) {
      for (int i = 0; i < v.size(); ++i) {
        v(i) = std::sin(0.37 * trial + 1.1 * i) * std::pow(10.0, (trial % 7) - 3);
        x(i) = std::cos(0.53 * trial + 0.7 * i) * 1e-3;
      }
      if (trial % 5 == 1) v(0) = -0.0;
      if (trial % 5 == 2) v(v.size() - 1) = 1e-170;  // its square underflows
      const double expected = dynamics.kinetic_energy(v);
      const double energy = operators.kinetic_energy(v, x, Mx);
      EXPECT_EQ(std::memcmp(&energy, &expected, sizeof(double)), 0) << "trial " << trial;
      const double alone = operators.kinetic_energy(v, expected_Mx);  // θ = ½'s, without M x
      EXPECT_EQ(std::memcmp(&alone, &expected, sizeof(double)), 0) << "trial " << trial;
      operators.apply_mass(x, expected_Mx);
      ASSERT_EQ(Mx.size(), expected_Mx.size());
      EXPECT_EQ(std::memcmp(Mx.data(), expected_Mx.data(), Mx.size() * sizeof(double)), 0) << "trial " << trial;
    }
  }
}

}  // namespace
}  // namespace csim
