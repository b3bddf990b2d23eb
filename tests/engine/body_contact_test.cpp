// The contact queries of Body (body.h), asked directly of each kind of body: a rigid body's point
// Jacobian against a central difference of its position map, its rotation axes, and an elastic body's
// contact surface, nodes and surface-point Jacobian against the motion of its nodes.
#include "engine/bodies/fe_body.h"
#include "engine/bodies/fixed_body.h"
#include "engine/bodies/point_mass.h"
#include "engine/bodies/rigid_body_2d.h"
#include "engine/bodies/rigid_body_3d.h"
#include "fem/mesh_generators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace csim {
namespace {

// The dense 3 × n matrix of a PointJacobian (n = the body's velocity components).
Eigen::MatrixXd dense(const PointJacobian& J, int n) {
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(3, n);
  for (int k = 0; k < J.count; ++k) D.col(J.index[k]) += J.column.col(k);
  return D;
}

// ∂x/∂v by central differences of x(q ⊕ ε e_k) = point_world(integrate_position(q, e_k, ε), local):
// the velocity map the Jacobian must be.
Eigen::MatrixXd central_difference(const Body& body, const Eigen::VectorXd& q, const Eigen::Vector3d& local) {
  const double eps = 1e-6;
  const int n = body.velocity_size();
  Eigen::MatrixXd D(3, n);
  Eigen::VectorXd plus(q.size()), minus(q.size());
  for (int k = 0; k < n; ++k) {
    const Eigen::VectorXd e = Eigen::VectorXd::Unit(n, k);
    body.integrate_position(q, e, eps, plus);
    body.integrate_position(q, e, -eps, minus);
    D.col(k) = (body.point_world(plus, local) - body.point_world(minus, local)) / (2 * eps);
  }
  return D;
}

TEST(BodyContact, RigidBody3dPointJacobianIsTheDerivativeOfItsPositionMap) {
  const RigidBody3d body(2.0, Eigen::Vector3d(0.1, 0.2, 0.3));
  Eigen::VectorXd q(7);
  const Eigen::Quaterniond rotation = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -1).normalized()) *
                                      Eigen::Quaterniond::Identity();
  q << 0.3, -0.2, 1.1, rotation.w(), rotation.x(), rotation.y(), rotation.z();
  const Eigen::Vector3d local(0.4, -0.25, 0.15);
  const Eigen::MatrixXd J = dense(body.point_jacobian(q, local), 6);
  EXPECT_LT((J - central_difference(body, q, local)).norm(), 1e-8);
  // A contact point given in world coordinates is the same material point.
  const Eigen::Vector3d x = body.pose(q) * local;
  EXPECT_LT((dense(body.world_point_jacobian(q, x), 6) - J).norm(), 1e-14);
  // Its rotation components are ω in the body frame: component 3 + i turns about e_i of the body.
  const auto axes = body.rotation_axes();
  ASSERT_EQ(axes.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(axes[i].first, 3 + i);
    const Eigen::Vector3d expected = body.pose(q).linear() * axes[i].second.cross(local);
    EXPECT_LT((J.col(axes[i].first) - expected).norm(), 1e-14);
  }
  EXPECT_FALSE(body.contact_surface(false).has_value());
  EXPECT_EQ(body.node_count(), 0);
  EXPECT_EQ(body.finite_elements(), nullptr);
}

TEST(BodyContact, RigidBody2dPointJacobianIsTheDerivativeOfItsPositionMap) {
  const RigidBody2d body(1.5, 0.02);
  const Eigen::Vector3d q(0.5, -0.3, 0.9);
  const Eigen::Vector3d local(0.2, 0.1, 0.0);
  const Eigen::MatrixXd J = dense(body.point_jacobian(q, local), 3);
  EXPECT_LT((J - central_difference(body, q, local)).norm(), 1e-8);
  EXPECT_LT((dense(body.world_point_jacobian(q, body.pose(q) * local), 3) - J).norm(), 1e-14);
  const auto axes = body.rotation_axes();
  ASSERT_EQ(axes.size(), 1u);
  EXPECT_EQ(axes[0].first, 2);
  EXPECT_EQ(axes[0].second, Eigen::Vector3d::UnitZ());
  EXPECT_FALSE(body.contact_surface(true).has_value());
}

// A 2D rigid body's points are asked for at every step (springs, probes) without forming its pose: they
// must be pose(q) * local to the bit, at any angle, for points on and off its plane and signed zeros.
TEST(BodyContact, RigidBody2dPointWorldIsItsPoseTimesThePointToTheBit) {
  const RigidBody2d body(1.5, 0.02);
  std::mt19937 random(41);
  std::uniform_real_distribution<double> uniform(-3.0, 3.0);
  const double specials[] = {0.0, -0.0, 1.0, -1.0, 0.5, 1e-300, 3.0e17};
  int differing = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Eigen::Vector3d q(uniform(random), uniform(random), 4.0 * uniform(random));
    Eigen::Vector3d local(uniform(random), uniform(random), trial % 3 == 0 ? uniform(random) : 0.0);
    if (trial < 343) {  // every combination of special values in x, y and the angle
      q(2) = specials[trial % 7];
      local(0) = specials[(trial / 7) % 7];
      local(1) = specials[(trial / 49) % 7];
    }
    const Eigen::Vector3d expected = body.pose(q) * local, got = body.point_world(q, local);
    for (int i = 0; i < 3; ++i)
      if (std::signbit(expected(i)) != std::signbit(got(i)) || !(expected(i) == got(i))) ++differing;
  }
  EXPECT_EQ(differing, 0);
}

// A spring asks for a point's position and Jacobian at once (Body::point_kinematics, springs.h): they
// must be point_world's and point_jacobian's to the bit, for every lumped body, at any turn, for points
// on and off the plane and signed zeros.
TEST(BodyContact, PointKinematicsArePointWorldAndPointJacobianToTheBit) {
  const RigidBody2d rigid_2d(1.5, 0.02);
  const RigidBody3d rigid_3d(2.0, Eigen::Vector3d(0.1, 0.2, 0.3));
  const PointMass point_2d(2, 1.5), point_3d(3, 1.5);
  std::mt19937 random(43);
  std::uniform_real_distribution<double> uniform(-3.0, 3.0);
  const double specials[] = {0.0, -0.0, 1.0, -1.0, 0.5, 1e-300, 3.0e17};
  const auto same = [](double a, double b) { return std::signbit(a) == std::signbit(b) && a == b; };
  int differing = 0, compared = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    Eigen::Vector3d local(uniform(random), uniform(random), trial % 3 == 0 ? uniform(random) : 0.0);
    double angle = 4.0 * uniform(random);
    if (trial < 343) {  // every combination of special values in x, y and the angle
      angle = specials[trial % 7];
      local(0) = specials[(trial / 7) % 7];
      local(1) = specials[(trial / 49) % 7];
    }
    Eigen::VectorXd q2(3), q3(7), p2(2), p3(3);
    q2 << uniform(random), uniform(random), angle;
    if (trial < 343) q2.head<2>() << specials[(trial / 49) % 7], specials[trial % 7];  // signed zeros in the sums
    const Eigen::Quaterniond turn =
        Eigen::Quaterniond(uniform(random), uniform(random), uniform(random), uniform(random)).normalized();
    q3 << uniform(random), uniform(random), uniform(random), turn.w(), turn.x(), turn.y(), turn.z();
    p2 << uniform(random), uniform(random);
    p3 << uniform(random), uniform(random), uniform(random);
    const std::pair<const Body*, const Eigen::VectorXd*> cases[] = {
        {&rigid_2d, &q2}, {&rigid_3d, &q3}, {&point_2d, &p2}, {&point_3d, &p3}};
    for (const auto& [body, q] : cases) {
      PointJacobian J;
      J.count = 5;  // stale: point_kinematics sets it
      const Eigen::Vector3d x = body->point_kinematics(*q, local, J);
      const Eigen::Vector3d expected_x = body->point_world(*q, local);
      const PointJacobian expected_J = body->point_jacobian(*q, local);
      for (int i = 0; i < 3; ++i) differing += !same(x(i), expected_x(i));
      if (J.count != expected_J.count) {
        ++differing;
        continue;
      }
      for (int k = 0; k < J.count; ++k) {
        differing += J.index[k] != expected_J.index[k];
        for (int i = 0; i < 3; ++i) differing += !same(J.column(i, k), expected_J.column(i, k));
      }
      ++compared;
    }
  }
  EXPECT_EQ(compared, 16000);
  EXPECT_EQ(differing, 0);
}

// The lumped bodies project a world point's Jacobian on the contact axes from the world lever arm
// (Body::project_world_point_jacobian); it must be the base's projection of world_point_jacobian
// (pose⁻¹, the body-frame point, its Jacobian) to round-off, component for component, at turned poses.
TEST(BodyContact, LumpedBodiesProjectTheirWorldPointJacobianToRoundOff) {
  const RigidBody3d rigid_3d(2.0, Eigen::Vector3d(0.1, 0.2, 0.3));
  const RigidBody2d rigid_2d(3.0, 0.4);
  const PointMass point_3d(3, 1.5), point_2d(2, 1.5);
  Eigen::VectorXd q3(7), q2(3), p3(3), p2(2);
  const Eigen::Quaterniond turn = Eigen::Quaterniond(0.8, -0.3, 0.4, 0.33).normalized();
  q3 << 0.7, -1.2, 2.5, turn.w(), turn.x(), turn.y(), turn.z();
  q2 << -0.4, 1.3, 2.2;
  p3 << 0.1, 0.2, -0.3;
  p2 << 0.1, 0.2;
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  const Eigen::Vector3d t1 = n.unitOrthogonal(), t2 = n.cross(t1);
  const Eigen::Vector3d n_plane = Eigen::Vector3d(0.6, -0.8, 0.0), t_plane(0.8, 0.6, 0.0);
  struct Case {
    const Body* body;
    const Eigen::VectorXd* q;
    Eigen::Vector3d x;  // m, world
    int axis_count;
  };
  const Case cases[] = {{&rigid_3d, &q3, Eigen::Vector3d(1.1, -0.9, 2.2), 3},
                        {&rigid_2d, &q2, Eigen::Vector3d(0.3, 0.8, 0.0), 2},
                        {&point_3d, &p3, Eigen::Vector3d(0.1, 0.2, -0.4), 3},
                        {&point_2d, &p2, Eigen::Vector3d(0.1, 0.25, 0.0), 2}};
  for (const Case& c : cases) {
    const Eigen::Vector3d* axes[3] = {c.axis_count == 3 ? &n : &n_plane, c.axis_count == 3 ? &t1 : &t_plane, &t2};
    ProjectedJacobian projected, expected;
    c.body->project_world_point_jacobian(*c.q, c.x, axes, c.axis_count, projected);
    c.body->Body::project_world_point_jacobian(*c.q, c.x, axes, c.axis_count, expected);
    ASSERT_EQ(projected.count, expected.count);
    ASSERT_EQ(projected.count, c.body->velocity_size());
    for (int j = 0; j < expected.count; ++j) {
      EXPECT_EQ(projected.index[j], expected.index[j]);
      for (int k = 0; k < c.axis_count; ++k)
        EXPECT_NEAR(projected.value(k, j), expected.value(k, j), 4e-16 * (1.0 + std::abs(expected.value(k, j))))
            << "body of " << c.body->velocity_size() << " components, axis " << k << ", component " << j;
    }
  }
}

TEST(BodyContact, PointMassAndFixedBodyNeitherRotateNorHaveASurface) {
  const PointMass point(3, 1.0);
  const FixedBody ground(Eigen::Isometry3d::Identity());
  for (const Body* body : {static_cast<const Body*>(&point), static_cast<const Body*>(&ground)}) {
    EXPECT_TRUE(body->rotation_axes().empty());
    EXPECT_FALSE(body->contact_surface(false).has_value());
    EXPECT_EQ(body->node_count(), 0);
    EXPECT_EQ(body->finite_elements(), nullptr);
  }
  const Eigen::Vector3d q(1.0, 2.0, 3.0);
  const Eigen::Vector3d local(0.1, 0.2, 0.3);
  EXPECT_LT((dense(point.point_jacobian(q, local), 3) - central_difference(point, q, local)).norm(), 1e-8);
  EXPECT_EQ(ground.surface_point_jacobian(Eigen::VectorXd(), SurfacePoint::at_node(0)).count, 0);
}

// A 2 × 1 quad4 rectangle (6 nodes: 0 1 2 along y = 0, 3 4 5 along y = 1) with x held on the left side.
FeBody rectangle_body() {
  const Mesh mesh = rectangle_mesh(2.0, 1.0, 2, 1, ElementType::quad4);
  std::vector<std::pair<int, int>> fixed;
  for (int node : mesh.node_sets.at("left")) fixed.emplace_back(node, 0);
  return FeBody(mesh, ElasticMaterial{1e6, 0.3, 1000.0}, 0.1, true, fixed);
}

TEST(BodyContact, ElasticBodyTouchesThroughItsBoundary) {
  const FeBody body = rectangle_body();
  EXPECT_EQ(body.finite_elements(), &body);
  EXPECT_TRUE(body.rotation_axes().empty());
  ASSERT_EQ(body.node_count(), 6);
  EXPECT_EQ(body.node_components(), 2);
  EXPECT_EQ(body.velocity_size(), 10);  // 12 dofs, x of the two left nodes held
  const std::optional<ContactSurface> surface = body.contact_surface(false);
  ASSERT_TRUE(surface.has_value());
  EXPECT_EQ(surface->reference_nodes, body.mesh().nodes);
  EXPECT_EQ(surface->geometry.segments.size(), 6u);  // the rectangle's boundary edges
  EXPECT_TRUE(surface->geometry.triangles.empty());
  EXPECT_EQ(surface->geometry.contact_nodes, (std::vector<int>{0, 1, 2, 3, 4, 5}));  // every node is on it
  EXPECT_TRUE(surface->geometry.curve.empty());
  EXPECT_FALSE(body.contact_surface(true)->geometry.curve.empty());  // smoothed: the curve too

  // Nodes: the held components have no velocity index, the others are the free dofs.
  for (int node = 0; node < 6; ++node) {
    EXPECT_EQ(body.node_reference(node), body.mesh().nodes[node]);
    for (int c = 0; c < 2; ++c) EXPECT_EQ(body.node_velocity_index(node, c), body.free_index(node, c));
  }
  const int left = body.mesh().node_sets.at("bottom_left").front();
  EXPECT_EQ(body.node_velocity_index(left, 0), -1);
  EXPECT_GE(body.node_velocity_index(left, 1), 0);
}

TEST(BodyContact, ElasticSurfacePointMovesWithItsJacobian) {
  const FeBody body = rectangle_body();
  const int n = body.velocity_size();
  const Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(n, -0.01, 0.02);
  const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(n, 0.3, -0.5);
  std::vector<Eigen::Vector3d> at_q, at_q_plus_v;
  const std::vector<int> every_node = {0, 1, 2, 3, 4, 5};
  body.surface_node_positions(q, every_node, at_q);
  body.surface_node_positions(q + v, every_node, at_q_plus_v);
  ASSERT_EQ(at_q.size(), 6u);
  for (int node = 0; node < 6; ++node)
    EXPECT_LT((at_q[node] - body.mesh().nodes[node] - body.node_displacement(q, node)).norm(), 1e-15);
  // The listed nodes alone (a detection's): theirs are the same to the bit, the others kept as they were.
  std::vector<Eigen::Vector3d> listed;
  body.surface_node_positions(q, {1, 4}, listed);
  ASSERT_EQ(listed.size(), 6u);
  for (int node = 0; node < 6; ++node)
    EXPECT_EQ(listed[node], node == 1 || node == 4 ? at_q[node] : body.mesh().nodes[node]) << node;
  body.surface_node_positions(q + v, {4}, listed);
  EXPECT_EQ(listed[4], at_q_plus_v[4]);
  EXPECT_EQ(listed[1], at_q[1]);
  // A point of the bottom edge between a held node and a free one, a quarter of the way along: its
  // position is linear in q, so J v is exactly its motion from q to q + v.
  SurfacePoint point;
  point.count = 2;
  point.nodes = {body.mesh().node_sets.at("bottom_left").front(), 1, 0, 0};
  point.weights = {0.75, 0.25, 0.0, 0.0};
  Eigen::Vector3d motion = Eigen::Vector3d::Zero();
  for (int k = 0; k < 2; ++k)
    motion += point.weights[k] * (at_q_plus_v[point.nodes[k]] - at_q[point.nodes[k]]);
  const Eigen::MatrixXd J = dense(body.surface_point_jacobian(q, point), n);
  EXPECT_LT((J * v - motion).norm(), 1e-15);
  // A node is a material point: its point Jacobian is its surface point's.
  EXPECT_EQ(dense(body.point_jacobian(q, body.mesh().nodes[1]), n),
            dense(body.surface_point_jacobian(q, SurfacePoint::at_node(1)), n));
}

}  // namespace
}  // namespace csim
