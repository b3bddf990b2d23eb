// BodyBlockOperator (body_block_operator.h) on a World of 3D rigid bodies and point masses, whose A = M is
// block diagonal by body: its W, dense and sparse, and its response A⁻¹ Hᵀ r against H M⁻¹ Hᵀ and
// M⁻¹ Hᵀ r formed from Dynamics' mass matrix; W symmetric to the bit; the factors' diagonal blocks W's.
#include "engine/contact_stage/body_block_operator.h"
#include "engine/bodies/rigid_body_3d.h"
#include "engine/dynamics.h"
#include "engine/structural_operators.h"
#include "tests/engine/test_worlds.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace csim {
namespace {

constexpr int kRigid = 12, kPoints = 3;

// Twelve rigid bodies of different masses and principal inertias, then three 3D point masses: 81
// unknowns, above StructuralOperators::kDenseLimit, so A is sparse and block diagonal.
World bodies() {
  World world;
  world.dimension = 3;
  for (int k = 0; k < kRigid; ++k) {
    BodyInstance b;
    b.name = "body" + std::to_string(k);
    b.body = std::make_unique<RigidBody3d>(1.0 + k, Eigen::Vector3d(0.1, 0.2, 0.3) * (1.0 + 0.5 * k));
    b.reference_position.setZero(7);
    b.reference_position(3) = 1.0;  // the identity rotation
    b.initial_position = b.reference_position;
    b.initial_velocity.setZero(6);
    world.bodies.push_back(std::move(b));
  }
  for (int k = 0; k < kPoints; ++k)
    world.bodies.push_back(test::point_mass("point" + std::to_string(k), 3, 0.5 + k, Eigen::Vector3d(k, 0, 0)));
  world.finalize_layout();
  return world;
}

// Contact c between body c and body c + 1 (c < 14), then one on body c − 14 against the ground: rows
// with deterministic entries on every unknown of their bodies, as a contact frame's rows are.
struct Rows {
  std::vector<SparseRow> storage;
  ProblemRows problem;
  Matrix H;
};

Rows contact_rows(const World& world) {
  Rows rows;
  const int bodies = kRigid + kPoints, contacts = bodies - 1 + 4;
  rows.storage.resize(3 * contacts);
  rows.H.setZero(3 * contacts, world.velocity_size);
  for (int c = 0; c < contacts; ++c) {
    const int a = c < bodies - 1 ? c : c - (bodies - 1), b = c < bodies - 1 ? c + 1 : -1;
    for (int k = 0; k < 3; ++k) {
      SparseRow& row = rows.storage[3 * c + k];
      for (const int body : {a, b}) {
        if (body < 0) continue;
        const BodyInstance& instance = world.bodies[body];
        for (int j = 0; j < instance.body->velocity_size(); ++j) {
          const double value = std::sin(1.0 + 0.7 * c + 1.3 * k + 0.37 * j + (body == a ? 0.0 : 2.0));
          row.add(instance.velocity_offset + j, value);
          rows.H(3 * c + k, instance.velocity_offset + j) += value;
        }
      }
      rows.problem.contact.push_back(&row);
    }
  }
  rows.problem.dimension = 3;
  return rows;
}

TEST(BodyBlockOperator, DelassusAndResponseAreThoseOfTheMassMatrix) {
  const World world = bodies();
  const Dynamics dynamics(world);
  StructuralOperators operators(dynamics);
  ASSERT_TRUE(operators.block_diagonal());
  const Rows rows = contact_rows(world);
  const Matrix M = Matrix(dynamics.mass());
  const Matrix M_inverse_Ht = M.ldlt().solve(rows.H.transpose());
  const Matrix W_reference = rows.H * M_inverse_Ht;
  const double scale = W_reference.cwiseAbs().maxCoeff();

  BodyBlockOperator op(operators);
  Matrix W;
  op.delassus(rows.problem, W);
  EXPECT_LE((W - W_reference).cwiseAbs().maxCoeff(), 1e-13 * scale);
  EXPECT_TRUE(W == W.transpose()) << "W not symmetric to the bit";

  SparseDelassus W_sparse;
  ASSERT_TRUE(op.sparse_delassus(rows.problem, W_sparse, true));
  const Matrix W_from_sparse = Matrix(W_sparse);
  EXPECT_LE((W_from_sparse - W_reference).cwiseAbs().maxCoeff(), 1e-13 * scale);
  EXPECT_TRUE(W_from_sparse == W_from_sparse.transpose()) << "sparse W not symmetric to the bit";
  // Only contacts that share a body have a block: 18 diagonal ones, 13 pairs of consecutive chain
  // contacts, and the ground contacts of bodies 0 to 3 with the 1 + 2 + 2 + 2 chain contacts of their
  // bodies, each pair both ways.
  EXPECT_EQ(W_sparse.nonZeros(), 9 * (18 + 2 * 13 + 2 * 7));

  BodyBlockDelassus blocks;
  ASSERT_TRUE(op.body_blocks(blocks));
  ASSERT_EQ(static_cast<int>(blocks.body.size()), rows.problem.contact_rows() / 3);
  for (int c = 0; c < static_cast<int>(blocks.body.size()); ++c) {
    Eigen::Matrix3d W_cc = Eigen::Matrix3d::Zero();
    for (int side = 0; side < 2; ++side) {
      if (blocks.body[c][side] < 0) continue;
      const Eigen::Map<const Eigen::Matrix<double, 3, 6, Eigen::RowMajor>> K(
          blocks.scaled_rows.data() + (2 * c + side) * 18);
      W_cc += K * K.transpose();
    }
    EXPECT_LE((W_cc - W_reference.block<3, 3>(3 * c, 3 * c)).cwiseAbs().maxCoeff(), 1e-13 * scale) << c;
  }

  Vector r(rows.H.rows());
  for (int a = 0; a < r.size(); ++a) r(a) = std::cos(0.3 * a);
  Vector v = Vector::Ones(world.velocity_size), expected = v + M_inverse_Ht * r;
  op.add_response(rows.problem, r, v);
  EXPECT_LE((v - expected).cwiseAbs().maxCoeff(), 1e-13 * expected.cwiseAbs().maxCoeff());

  // Two halves: A⁻¹ f body by body, and the velocity v_k + A⁻¹ (f + Hᵀ r).
  Vector f(world.velocity_size), v_k = Vector::Constant(world.velocity_size, 0.25), v_next;
  for (int i = 0; i < f.size(); ++i) f(i) = std::sin(0.9 * i);
  op.forward_half(f);
  op.velocity(rows.problem, r, v_k, v_next);
  const Vector expected_next = v_k + M.ldlt().solve(f + rows.H.transpose() * r);
  EXPECT_LE((v_next - expected_next).cwiseAbs().maxCoeff(), 1e-13 * expected_next.cwiseAbs().maxCoeff());
}

}  // namespace
}  // namespace csim
