// Global assembly (fem/assembly.h) on problems with closed-form answers: a bar in uniform tension,
// resultants of pressure loads, total mass; and the assembly time of a 160 × 160 quad4 mesh.
#include "fem/assembly.h"

#include "tests/fem/test_meshes.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <map>
#include <string>
#include <vector>

namespace csim {
namespace {

constexpr double kYoung = 2.1e11;                             // Pa
constexpr double kDensity = 7800.0;                           // kg/m³
constexpr double kThickness = 0.1;                            // m
constexpr double kTraction = 1.0e7;                           // Pa, tensile
constexpr double kLength = 2.0, kHeight = 0.5, kDepth = 0.4;  // m

void rotate(Mesh& mesh, const Eigen::Matrix3d& rotation) {
  for (Eigen::Vector3d& x : mesh.nodes) x = rotation * x;
}

Eigen::Matrix3d rotation_about(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

Mesh bar(ElementType type) {
  return type == ElementType::hexa8 ? test::box(8, 2, 2, kLength, kHeight, kDepth)
                                    : test::rectangle(type, 8, 2, kLength, kHeight);
}

// A bar [0, L] × [0, H] (× [0, W]) pulled by the traction p on its right end (pressure −p): left
// end fixed along x, lateral rigid motions removed at the left corners only, so that σxx = p is
// uniform and, in plane strain, u_x(L) = (1 − ν²) p L / E (σzz = ν p); in 3D, u_x(L) = p L / E.
struct TensionResult {
  Eigen::VectorXd u, f;
  Eigen::SparseMatrix<double> K;
  std::vector<Stress> stresses;
};

TensionResult tension(const Mesh& mesh, double poisson) {
  const FeModel model{mesh, {kYoung, poisson, kDensity}, kThickness};
  const int d = mesh.dofs_per_node();
  std::map<int, double> prescribed;
  for (int node : mesh.node_sets.at("left")) prescribed[d * node] = 0.0;
  auto node_at = [&](const Eigen::Vector3d& x) {
    for (int i = 0; i < static_cast<int>(mesh.nodes.size()); ++i)
      if ((mesh.nodes[i] - x).norm() < 1e-12) return i;
    throw std::runtime_error("no node there");
  };
  prescribed[d * node_at({0, 0, 0}) + 1] = 0.0;
  if (d == 3) {
    // Rotations about y and z move u_x on the left end, already fixed; the one about x is stopped
    // here (and the last constraint is redundant but consistent with the lateral contraction).
    prescribed[d * node_at({0, 0, kDepth}) + 1] = 0.0;
    prescribed[d * node_at({0, 0, 0}) + 2] = 0.0;
    prescribed[d * node_at({0, kHeight, 0}) + 2] = 0.0;
  }
  TensionResult result;
  result.K = assemble_stiffness(model);
  result.f = pressure_load(model, mesh.face_sets.at("right"), -kTraction);
  result.u = test::solve(result.K, result.f, prescribed);
  result.stresses = element_stresses(model, result.u);
  return result;
}

TEST(Tension, TipDisplacementIsPLOverEWithoutPoisson) {
  for (ElementType type : {ElementType::quad4, ElementType::quad8, ElementType::hexa8}) {
    const Mesh mesh = bar(type);
    const TensionResult r = tension(mesh, 0.0);
    const int d = mesh.dofs_per_node();
    const double expected = kTraction * kLength / kYoung;  // m
    for (int node : mesh.node_sets.at("right"))
      EXPECT_NEAR(r.u(d * node), expected, 1e-12 * expected) << to_string(type) << " node " << node;
    for (int node = 0; node < static_cast<int>(mesh.nodes.size()); ++node)
      for (int i = 1; i < d; ++i) EXPECT_NEAR(r.u(d * node + i), 0.0, 1e-12 * expected);
    for (const Stress& stress : r.stresses) {
      EXPECT_NEAR(stress(0), kTraction, 1e-10 * kTraction) << to_string(type);
      for (int i = 1; i < 6; ++i) EXPECT_NEAR(stress(i), 0.0, 1e-10 * kTraction) << to_string(type);
    }
    // ½ uᵀ K u = σ² V / (2E), the strain energy of uniform uniaxial stress.
    const double volume = kLength * kHeight * (d == 2 ? kThickness : kDepth);
    const double energy = kTraction * kTraction * volume / (2 * kYoung);
    EXPECT_NEAR(strain_energy(r.K, r.u), energy, 1e-10 * energy);
    EXPECT_NEAR(strain_energy(r.K, r.u), 0.5 * r.f.dot(r.u), 1e-10 * energy);
  }
}

TEST(Tension, PlaneStrainPoissonEffect) {
  const double nu = 0.3;
  for (ElementType type : {ElementType::quad4, ElementType::quad8, ElementType::hexa8}) {
    const Mesh mesh = bar(type);
    const TensionResult r = tension(mesh, nu);
    const int d = mesh.dofs_per_node();
    const double expected = (d == 2 ? 1 - nu * nu : 1.0) * kTraction * kLength / kYoung;
    for (int node : mesh.node_sets.at("right"))
      EXPECT_NEAR(r.u(d * node), expected, 1e-11 * expected) << to_string(type);
    for (const Stress& stress : r.stresses) {
      EXPECT_NEAR(stress(0), kTraction, 1e-9 * kTraction) << to_string(type);
      EXPECT_NEAR(stress(1), 0.0, 1e-9 * kTraction);
      EXPECT_NEAR(stress(2), d == 2 ? nu * kTraction : 0.0, 1e-9 * kTraction) << to_string(type);
    }
  }
}

// Σ_a f_a for a pressure p on faces: −p ∫ n dA, computed from the geometry alone.
Eigen::Vector3d resultant(const Mesh& mesh, const Eigen::VectorXd& f) {
  const int d = mesh.dofs_per_node();
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int node = 0; node < static_cast<int>(mesh.nodes.size()); ++node)
    total.head(d) += f.segment(d * node, d);
  return total;
}

TEST(PressureLoad, ResultantIsPressureTimesAreaAlongMinusNormal) {
  const double p = 3.0e5;  // Pa
  const Eigen::Matrix3d R2 = rotation_about(Eigen::Vector3d::UnitZ(), 0.6);
  const Eigen::Matrix3d R3 = rotation_about(Eigen::Vector3d(1, 2, 3), 0.8);
  for (ElementType type : {ElementType::quad4, ElementType::quad8, ElementType::hexa8}) {
    Mesh mesh = bar(type);
    const bool solid = type == ElementType::hexa8;
    rotate(mesh, solid ? R3 : R2);
    const FeModel model{mesh, {kYoung, 0.3, kDensity}, kThickness};
    const double depth = solid ? kDepth : kThickness;
    const std::map<std::string, std::pair<Eigen::Vector3d, double>> sides{
        {"right", {Eigen::Vector3d::UnitX(), kHeight * depth}},
        {"left", {-Eigen::Vector3d::UnitX(), kHeight * depth}},
        {"top", {Eigen::Vector3d::UnitY(), kLength * depth}},
        {"bottom", {-Eigen::Vector3d::UnitY(), kLength * depth}}};
    for (const auto& [side, normal_area] : sides) {
      const auto& [normal, area] = normal_area;
      const Eigen::Vector3d expected = -p * area * ((solid ? R3 : R2) * normal);
      const Eigen::Vector3d total =
          resultant(mesh, pressure_load(model, mesh.face_sets.at(side), p));
      EXPECT_LT((total - expected).norm(), 1e-12 * expected.norm())
          << to_string(type) << " " << side;
    }
  }
}

TEST(PressureLoad, CurvedAndWarpedFacesGiveTheProjectedArea) {
  const double p = -2.0e5;  // Pa: a pull
  // quad8 edges made curved by moving every node: ∫ n ds = rotation by −90° of the chord.
  Mesh curved = test::rectangle(ElementType::quad8, 4, 2, kLength, kHeight);
  test::distort(curved, 0.03);
  const FeModel plane{curved, {kYoung, 0.3, kDensity}, kThickness};
  for (const auto& [side, faces] : curved.face_sets) {
    Eigen::Vector3d expected = Eigen::Vector3d::Zero();
    for (const Face& face : faces) {
      const Eigen::Vector3d chord = curved.nodes[face.nodes[1]] - curved.nodes[face.nodes[0]];
      expected += -p * kThickness * Eigen::Vector3d(chord.y(), -chord.x(), 0.0);
    }
    const Eigen::Vector3d total = resultant(curved, pressure_load(plane, faces, p));
    EXPECT_LT((total - expected).norm(), 1e-12 * expected.norm()) << side;
  }
  // Warped hexa8 faces (bilinear surfaces): ∫ n dA = ½ (x2 − x0) × (x3 − x1).
  Mesh warped = test::box(3, 2, 2, kLength, kHeight, kDepth);
  test::distort(warped, 0.03);
  const FeModel solid{warped, {kYoung, 0.3, kDensity}, kThickness};
  for (const auto& [side, faces] : warped.face_sets) {
    Eigen::Vector3d expected = Eigen::Vector3d::Zero();
    for (const Face& face : faces) {
      const auto& x = warped.nodes;
      const auto& n = face.nodes;
      expected += -p * 0.5 * (x[n[2]] - x[n[0]]).cross(x[n[3]] - x[n[1]]);
    }
    const Eigen::Vector3d total = resultant(warped, pressure_load(solid, faces, p));
    EXPECT_LT((total - expected).norm(), 1e-12 * expected.norm()) << side;
  }
}

TEST(PressureLoad, NodalSharesOfAStraightFace) {
  const double p = 1.0e6;  // Pa
  // Consistent load of a straight quadratic edge: 1/6, 1/6, 2/3 of the edge's force (∫ N_a ds / L).
  const Mesh mesh = test::rectangle(ElementType::quad8, 1, 1, kLength, kHeight);
  const FeModel model{mesh, {kYoung, 0.3, kDensity}, kThickness};
  const Face& right = mesh.face_sets.at("right").front();
  const Eigen::VectorXd f = pressure_load(model, {right}, p);
  const double total = p * kHeight * kThickness;
  EXPECT_NEAR(f(2 * right.nodes[0]), -total / 6, 1e-12 * total);
  EXPECT_NEAR(f(2 * right.nodes[1]), -total / 6, 1e-12 * total);
  EXPECT_NEAR(f(2 * right.nodes[2]), -2 * total / 3, 1e-12 * total);
}

TEST(PressureLoad, MalformedFacesThrowNamingThem) {
  const Mesh mesh = test::rectangle(ElementType::quad4, 2, 1, kLength, kHeight);
  const FeModel model{mesh, {kYoung, 0.3, kDensity}, kThickness};
  std::vector<Face> faces = mesh.face_sets.at("bottom");
  faces[1].nodes.push_back(0);
  try {
    pressure_load(model, faces, 1.0);
    ADD_FAILURE() << "a 3-node face accepted on a quad4 mesh";
  } catch (const FemError& error) {
    EXPECT_NE(std::string(error.what()).find("face 1 (element 1)"), std::string::npos)
        << error.what();
  }
  faces[1].nodes = {0, 1000};
  EXPECT_THROW(pressure_load(model, faces, 1.0), FemError);
}

TEST(Mass, TotalIsDensityTimesVolumePerDirection) {
  for (ElementType type : {ElementType::quad4, ElementType::quad8, ElementType::hexa8}) {
    Mesh mesh = bar(type);
    test::distort(mesh, 0.02, /*interior_only=*/true);  // the outline, hence the volume, is kept
    const FeModel model{mesh, {kYoung, 0.3, kDensity}, kThickness};
    const int d = mesh.dofs_per_node();
    const double mass = kDensity * kLength * kHeight * (d == 2 ? kThickness : kDepth);  // kg
    for (bool lumped : {false, true}) {
      const Eigen::SparseMatrix<double> M = assemble_mass(model, lumped);
      ASSERT_EQ(M.rows(), mesh.dof_count());
      Eigen::MatrixXd per_direction = Eigen::MatrixXd::Zero(d, d);  // 1_iᵀ M 1_j
      for (int column = 0; column < M.outerSize(); ++column)
        for (Eigen::SparseMatrix<double>::InnerIterator it(M, column); it; ++it)
          per_direction(it.row() % d, column % d) += it.value();
      EXPECT_LT((per_direction - mass * Eigen::MatrixXd::Identity(d, d)).cwiseAbs().maxCoeff(),
                1e-12 * mass)
          << to_string(type) << (lumped ? " lumped" : " consistent");
      if (lumped) {
        EXPECT_EQ(M.nonZeros(), mesh.dof_count());
        EXPECT_GT(Eigen::VectorXd(M.diagonal()).minCoeff(), 0.0) << to_string(type);
      }
    }
  }
}

TEST(Assembly, StiffnessIsSymmetricWithTheMeshPattern) {
  Mesh mesh = test::rectangle(ElementType::quad8, 3, 2, kLength, kHeight);
  test::distort(mesh, 0.02);
  const Eigen::SparseMatrix<double> K =
      assemble_stiffness({mesh, {kYoung, 0.3, kDensity}, kThickness});
  EXPECT_EQ(K.rows(), mesh.dof_count());
  EXPECT_EQ((K - Eigen::SparseMatrix<double>(K.transpose())).norm(), 0.0);
  EXPECT_THROW(
      element_stresses({mesh, {kYoung, 0.3, kDensity}, kThickness}, Eigen::VectorXd::Zero(3)),
      FemError);
  EXPECT_THROW(strain_energy(K, Eigen::VectorXd::Zero(3)), FemError);
  EXPECT_THROW(assemble_stiffness({mesh, {kYoung, 0.3, kDensity}, 0.0}), FemError);
}

TEST(Assembly, TimeOf160By160Quad4) {
  const Mesh mesh = test::rectangle(ElementType::quad4, 160, 160, 1.0, 1.0);
  const FeModel model{mesh, {kYoung, 0.3, kDensity}, kThickness};
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const Eigen::SparseMatrix<double> K = assemble_stiffness(model);
  const auto stiffness_done = Clock::now();
  const Eigen::SparseMatrix<double> M = assemble_mass(model, false);
  const auto mass_done = Clock::now();
  const Eigen::SparseMatrix<double> M_lumped = assemble_mass(model, true);
  const auto lumped_done = Clock::now();
  auto ms = [](auto duration) {
    return std::chrono::duration<double, std::milli>(duration).count();
  };
  std::cout << "[ timing   ] 160×160 quad4, " << K.rows() << " dofs, " << K.nonZeros()
            << " nonzeros: K " << ms(stiffness_done - start) << " ms, consistent M "
            << ms(mass_done - stiffness_done) << " ms, lumped M " << ms(lumped_done - mass_done)
            << " ms\n";
  EXPECT_EQ(K.rows(), 2 * 161 * 161);
  EXPECT_EQ(M.rows(), K.rows());
  EXPECT_EQ(M_lumped.nonZeros(), K.rows());
}

}  // namespace
}  // namespace csim
