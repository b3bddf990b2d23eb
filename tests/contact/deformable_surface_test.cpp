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

// A body's nodes that its surface's geometry does not name (interior nodes) are not the BVH's: the
// surface's contacts, as it moves, are those of the same square numbered alone, wherever the interior
// nodes are; a position list of another length is refused.
TEST(DeformableSurface, NodesOffTheGeometryDoNotCount) {
  DeformableSurfaceGeometry interleaved;  // the square's corners as nodes 0, 2, 3, 5 of six
  interleaved.segments = {{0, 2}, {2, 3}, {3, 5}, {5, 0}};
  interleaved.contact_nodes = {0, 2, 3, 5};
  const auto body_nodes = [](const Eigen::Vector3d& offset, double interior) {
    const std::vector<Eigen::Vector3d> corners = square_nodes(offset);
    return std::vector<Eigen::Vector3d>{corners[0], Eigen::Vector3d(interior, 0, 0), corners[1], corners[2],
                                        Eigen::Vector3d(0, interior, 0), corners[3]};
  };
  CollisionWorld plain(true), with_interior(true);
  for (CollisionWorld* world : {&plain, &with_interior}) world->set_pose(world->add_object(0, Sphere{0.5}, true), Eigen::Isometry3d::Identity());
  const int a = plain.add_deformable_surface(1, square_nodes(Eigen::Vector3d(0.4, -0.3, 0)), square());
  const int b = with_interior.add_deformable_surface(1, body_nodes(Eigen::Vector3d(0.4, -0.3, 0), 1e6), interleaved);
  const int renumbered[] = {0, 2, 3, 5};
  // Each corner in turn in the ball (node 0, then 2, 3, 5), then none.
  for (const Eigen::Vector3d& offset : {Eigen::Vector3d(0.4, -0.3, 0), Eigen::Vector3d(-0.9, -0.2, 0), Eigen::Vector3d(-0.9, -1.1, 0),
                                       Eigen::Vector3d(-0.2, -0.7, 0), Eigen::Vector3d(10, 0, 0)}) {
    plain.set_node_positions(a, square_nodes(offset));
    with_interior.set_node_positions(b, body_nodes(offset, offset.x() > 5 ? 0.0 : -1e6));
    std::vector<ContactPoint> expected, found;
    for (auto [world, out] : {std::pair{&plain, &expected}, std::pair{&with_interior, &found}}) {
      world->update(1e-3);
      world->find_contacts(*out);
    }
    ASSERT_EQ(found.size(), expected.size()) << offset.transpose();
    for (std::size_t i = 0; i < found.size(); ++i) {
      EXPECT_EQ(found[i].key.feature, renumbered[expected[i].key.feature]);
      EXPECT_EQ(found[i].gap, expected[i].gap);
      EXPECT_EQ(found[i].point_b, expected[i].point_b);
    }
    if (offset.x() < 5) {
      EXPECT_FALSE(found.empty());
    }
  }
  EXPECT_THROW(with_interior.set_node_positions(b, square_nodes(Eigen::Vector3d::Zero())), std::invalid_argument);
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


// Face features: a 2 × 1 surface whose top edge is split at x = 1 (nodes 0..4, segments outward).
DeformableSurfaceGeometry slab() {
  DeformableSurfaceGeometry g;
  g.segments = {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 0}};
  g.contact_nodes = {0, 1, 2, 3, 4};
  return g;
}
std::vector<Eigen::Vector3d> slab_nodes() {
  return {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {0, 1, 0}};
}

std::vector<ContactPoint> face_contacts(const Shape& shape, const Eigen::Isometry3d& pose, double margin,
                                        SurfaceFeatures features = SurfaceFeatures::faces) {
  CollisionWorld world(true);
  const int surface = world.add_deformable_surface(1, slab_nodes(), slab());
  const int object = world.add_object(0, shape, false);
  world.set_surface_features(surface, 0, features);
  world.set_pose(object, pose);
  world.update(margin);
  std::vector<ContactPoint> contacts;
  world.find_contacts(contacts);
  return contacts;
}

TEST(DeformableSurface, BoxVerticesLandOnFacesWithInterpolationWeights) {
  // A 0.5 × 0.2 box whose bottom corners sit at x = 0.6 and 1.1, 0.01 above the top face, one
  // penetrating by 0.002 after a small rotation: both corners are between nodes, where node
  // features see nothing.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.85, 1.11, 0);
  const auto contacts = face_contacts(Box{Eigen::Vector3d(0.25, 0.1, 0.5)}, pose, 0.05);
  ASSERT_EQ(contacts.size(), 2u);
  for (const ContactPoint& c : contacts) {
    EXPECT_EQ(c.key.object_a, 0);  // the surface was added first
    EXPECT_NEAR(c.gap, 0.01, 1e-14);
    EXPECT_TRUE(c.normal.isApprox(Eigen::Vector3d::UnitY(), 1e-14));  // from the surface to the box
    EXPECT_NEAR((c.point_b - c.point_a).dot(c.normal), c.gap, 1e-14);
    ASSERT_EQ(c.surface.count, 2);
    // The weights reproduce the surface point from the nodes.
    const auto nodes = slab_nodes();
    const Eigen::Vector3d x = c.surface.weights[0] * nodes[c.surface.nodes[0]] + c.surface.weights[1] * nodes[c.surface.nodes[1]];
    EXPECT_TRUE(x.isApprox(c.point_a, 1e-14));
  }
  // Corner 0 (x = 0.6) on segment 3-4 (x from 1 to 0): weight 0.4 on node 3; corner 1 (x = 1.1) on 2-3.
  EXPECT_EQ(contacts[1].key.feature, -1);
  EXPECT_EQ(contacts[1].surface.nodes[0], 3);
  EXPECT_NEAR(contacts[1].surface.weights[0], 0.6, 1e-14);
  EXPECT_EQ(contacts[0].key.feature, -2);
  EXPECT_EQ(contacts[0].surface.nodes[0], 2);
  EXPECT_NEAR(contacts[0].surface.weights[0], 0.1, 1e-14);
  // With node features only, the corners are not seen: node 3, under the box, is the one contact.
  const auto nodes_only = face_contacts(Box{Eigen::Vector3d(0.25, 0.1, 0.5)}, pose, 0.05, SurfaceFeatures::nodes);
  ASSERT_EQ(nodes_only.size(), 1u);
  EXPECT_EQ(nodes_only[0].key.feature, 3);
  EXPECT_EQ(face_contacts(Box{Eigen::Vector3d(0.25, 0.1, 0.5)}, pose, 0.05, SurfaceFeatures::both).size(), 3u);
}

TEST(DeformableSurface, PenetratingVertexAndSphereBeyondACorner) {
  // A rotated box whose lowest corner is 0.003 inside the top face: gap −0.003, the face's normal.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(std::atan2(0.1, 0.25) , Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.5, 1.0 - 0.003, 0) - pose.linear() * Eigen::Vector3d(-0.25, -0.1, 0);
  auto contacts = face_contacts(Box{Eigen::Vector3d(0.25, 0.1, 0.5)}, pose, 1e-3);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].key.feature, -1);  // corner 0, (−hx, −hy), the lowest after a positive turn
  EXPECT_NEAR(contacts[0].gap, -0.003, 1e-14);
  EXPECT_TRUE(contacts[0].normal.isApprox(Eigen::Vector3d::UnitY(), 1e-14));
  // A disk of radius 0.1 up and right of the corner node (2, 1): outside, its distance to the corner
  // minus the radius, the normal along the diagonal (neither face's normal).
  pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(2.06, 1.08, 0);
  contacts = face_contacts(Sphere{0.1}, pose, 0.01);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_NEAR(contacts[0].gap, 0.0, 1e-14);
  EXPECT_TRUE(contacts[0].normal.isApprox(Eigen::Vector3d(0.6, 0.8, 0), 1e-14));
  EXPECT_EQ(contacts[0].key.feature, -1);
}

TEST(DeformableSurface, CubeVertexOnATriangleIn3d) {
  // The unit square z = 0 as two triangles (outward normal +z), a cube corner above its interior.
  DeformableSurfaceGeometry g;
  g.triangles = {{0, 1, 2}, {0, 2, 3}};
  g.contact_nodes = {0, 1, 2, 3};
  CollisionWorld world(false);
  const int surface = world.add_deformable_surface(
      1, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, g);
  const int cube = world.add_object(0, Box{Eigen::Vector3d::Constant(0.1)}, false);
  world.set_surface_features(surface, 0, SurfaceFeatures::faces);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.5, 0.4, 0.1 - 0.001);  // bottom face 0.001 inside
  world.set_pose(cube, pose);
  world.update(1e-3);
  std::vector<ContactPoint> contacts;
  world.find_contacts(contacts);
  ASSERT_EQ(contacts.size(), 4u);  // the four bottom vertices
  for (const ContactPoint& c : contacts) {
    EXPECT_NEAR(c.gap, -0.001, 1e-14);
    EXPECT_TRUE(c.normal.isApprox(Eigen::Vector3d::UnitZ(), 1e-14));
    ASSERT_EQ(c.surface.count, 3);
    EXPECT_NEAR(c.surface.weights[0] + c.surface.weights[1] + c.surface.weights[2], 1.0, 1e-14);
    EXPECT_GE(std::min({c.surface.weights[0], c.surface.weights[1], c.surface.weights[2]}), 0.0);
  }
}

}  // namespace
}  // namespace csim
