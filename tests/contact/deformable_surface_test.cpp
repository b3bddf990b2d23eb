// Deformable surfaces in the collision world: node-to-shape gaps against closed forms, and the FCL
// BVH refit (a surface moved away loses its contacts, moved back finds them again).
#include "contact/collision_world.h"

#include <gtest/gtest.h>

namespace csim {
namespace {

// A 1 × 1 square's boundary in the plane: 4 nodes, 4 segments.
DeformableSurfaceGeometry square() {
  DeformableSurfaceGeometry g;
  g.segments = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  g.contact_nodes = {0, 1, 2, 3};
  return g;
}

std::vector<Eigen::Vector3d> square_nodes(const Eigen::Vector3d& offset) {
  return {offset + Eigen::Vector3d(0, 0, 0), offset + Eigen::Vector3d(1, 0, 0), offset + Eigen::Vector3d(1, 1, 0),
          offset + Eigen::Vector3d(0, 1, 0)};
}

TEST(DeformableSurface, NodesOnAHalfspaceHaveTheirExactGaps) {
  CollisionWorld world(true);
  const int ground = world.add_object(0, Halfspace{Eigen::Vector3d::UnitY(), 0.0}, true);
  auto nodes = square_nodes(Eigen::Vector3d(0, 0.001, 0));
  nodes[1].y() = -0.002;  // one bottom node penetrates
  const int surface = world.add_deformable_surface(1, nodes, square());
  world.update(0.01);
  std::vector<ContactPoint> contacts;
  world.find_contacts(contacts);
  ASSERT_EQ(contacts.size(), 2u);
  EXPECT_EQ(contacts[0].key.object_a, ground);
  EXPECT_EQ(contacts[0].key.object_b, surface);
  EXPECT_EQ(contacts[0].key.feature, 0);
  EXPECT_NEAR(contacts[0].gap, 0.001, 1e-15);
  EXPECT_NEAR(contacts[1].gap, -0.002, 1e-15);
  EXPECT_TRUE(contacts[1].normal.isApprox(Eigen::Vector3d::UnitY()));  // from the ground to the node
  EXPECT_NEAR((contacts[1].point_b - contacts[1].point_a).dot(contacts[1].normal), contacts[1].gap, 1e-15);
}

TEST(DeformableSurface, RefittedBvhFollowsTheNodes) {
  CollisionWorld world(true);
  const Eigen::Isometry3d at_origin = Eigen::Isometry3d::Identity();
  const int ball = world.add_object(0, Sphere{0.5}, true);
  world.set_pose(ball, at_origin);
  const int surface = world.add_deformable_surface(1, square_nodes(Eigen::Vector3d(0.4, -0.3, 0)), square());
  world.update(1e-3);
  std::vector<ContactPoint> contacts;
  world.find_contacts(contacts);
  ASSERT_EQ(contacts.size(), 1u);  // node 0 at (0.4, −0.3): distance 0.5, gap 0
  EXPECT_NEAR(contacts[0].gap, 0.0, 1e-15);
  world.set_node_positions(surface, square_nodes(Eigen::Vector3d(10, 0, 0)));
  world.update(1e-3);
  world.find_contacts(contacts);
  EXPECT_TRUE(contacts.empty());
  world.set_node_positions(surface, square_nodes(Eigen::Vector3d(0.4, -0.3, 0)));
  world.update(1e-3);
  world.find_contacts(contacts);
  EXPECT_EQ(contacts.size(), 1u);
}

TEST(DeformableSurface, NodeInsideABoxGoesToTheNearestFace) {
  CollisionWorld world(true);
  const int box = world.add_object(0, Box{Eigen::Vector3d(1, 0.5, 0.5)}, true);
  world.set_pose(box, Eigen::Isometry3d::Identity());
  auto nodes = square_nodes(Eigen::Vector3d(0.2, 0.45, 0));  // node 0 at (0.2, 0.45): 0.05 below the top
  world.add_deformable_surface(1, nodes, square());
  world.update(0.0);
  std::vector<ContactPoint> contacts;
  world.find_contacts(contacts);
  ASSERT_EQ(contacts.size(), 1u);  // node 0 is inside; node 1, at x = 1.2, is 0.2 outside
  EXPECT_NEAR(contacts[0].gap, -0.05, 1e-15);
  EXPECT_TRUE(contacts[0].normal.isApprox(Eigen::Vector3d::UnitY()));
}

}  // namespace
}  // namespace csim
