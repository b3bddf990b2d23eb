// The ties as equality rows (Moreau–Jean): the gaps vanish on the reference configuration and on any
// rigid motion of ring and hub together, and each row is the derivative of its gap along the velocity
// components as the stepper integrates them (a 3D hub's quaternion included), by central differences,
// in the plane and in space.
#include "engine/tie_rows.h"
#include "engine/bodies/fe_body.h"
#include "tools/scene/scene.h"

#include <gtest/gtest.h>

namespace csim {
namespace {

std::unique_ptr<Scene> coarse_ring(bool space) {
  if (space)
    return load_scene(CSIM_SOURCE_DIR "/scenes/rolling-ring-3d/scene.yaml",
                      {"parameters.divisions_circumferential=8", "parameters.divisions_radial=2"});
  return load_scene(CSIM_SOURCE_DIR "/scenes/rolling-ring/scene.yaml",
                    {"parameters.divisions_circumferential=8", "parameters.divisions_radial=2"});
}

// The World's reference configuration q.
Vector reference(const World& world) {
  Vector q(world.position_size);
  for (const BodyInstance& b : world.bodies) q.segment(b.position_offset, b.body->position_size()) = b.reference_position;
  return q;
}

// Positions q moved by the velocity increment d (each body integrates its own slice).
Vector moved(const World& world, const Vector& q, const Vector& d) {
  Vector out = q;
  for (const BodyInstance& b : world.bodies) {
    if (b.body->fixed()) continue;
    b.body->integrate_position(b.positions(q), d.segment(b.velocity_offset, b.body->velocity_size()), 1.0,
                               out.segment(b.position_offset, b.body->position_size()));
  }
  return out;
}

// Every velocity component perturbed, the hub turned by 0.7 rad about its axis (and tilted in 3D).
Vector some_increment(const World& world, bool space) {
  Vector d(world.velocity_size);
  for (int k = 0; k < d.size(); ++k) d(k) = 0.01 * std::sin(1.3 * k + 0.2);
  const int hub = world.bodies[world.body_index("hub")].velocity_offset;
  d(hub + (space ? 5 : 2)) = 0.7;
  return d;
}

class TieRowsTest : public ::testing::TestWithParam<bool> {};

TEST_P(TieRowsTest, GapsVanishOnRigidMotions) {
  const auto scene = coarse_ring(GetParam());
  const World& world = scene->world;
  TieRows ties(world);
  // x and y of the 8 inner nodes (two layers in 3D, where z is held on every node: no row)
  EXPECT_EQ(ties.size(), 2 * 8 * (GetParam() ? 2 : 1));
  Vector gaps;
  ties.compute_gaps(reference(world), gaps);
  EXPECT_LT(gaps.lpNorm<Eigen::Infinity>(), 1e-15);
  // Turn the hub by 0.7 rad, shift it, and move every ring node with it as one of its material points.
  Vector d = Vector::Zero(world.velocity_size);
  const BodyInstance& hub = world.bodies[world.body_index("hub")];
  d(hub.velocity_offset) = 0.3;
  d(hub.velocity_offset + (GetParam() ? 5 : 2)) = 0.7;
  Vector q = moved(world, reference(world), d);
  const Eigen::Isometry3d motion =
      hub.body->pose(hub.positions(q)) * hub.body->pose(hub.positions(reference(world))).inverse();
  const BodyInstance& ring = world.bodies[world.body_index("ring")];
  const auto& fe = *ring.body->finite_elements();
  for (int node = 0; node < static_cast<int>(fe.mesh().nodes.size()); ++node) {
    const Eigen::Vector3d X = fe.mesh().nodes[node];
    const Eigen::Vector3d u = motion * X - X;
    for (int c = 0; c < fe.dofs_per_node(); ++c)
      if (fe.free_index(node, c) >= 0) q(ring.position_offset + fe.free_index(node, c)) = u(c);
  }
  ties.compute_gaps(q, gaps);
  EXPECT_LT(gaps.lpNorm<Eigen::Infinity>(), 1e-14);
  // The hub alone turned: the gaps are the tied nodes' chords, of order the inner radius.
  ties.compute_gaps(moved(world, reference(world), d), gaps);
  EXPECT_GT(gaps.lpNorm<Eigen::Infinity>(), 0.3);
}

TEST_P(TieRowsTest, RowsAreTheGapsDerivatives) {
  const auto scene = coarse_ring(GetParam());
  const World& world = scene->world;
  TieRows ties(world);
  const Vector q = moved(world, reference(world), some_increment(world, GetParam()));
  ties.linearize(q);
  const double h = 1e-6;
  double worst = 0.0;
  Vector plus, minus;
  for (int k = 0; k < world.velocity_size; ++k) {
    Vector unit = Vector::Zero(world.velocity_size);
    unit(k) = 1.0;
    ties.compute_gaps(moved(world, q, h * unit), plus);
    ties.compute_gaps(moved(world, q, -h * unit), minus);
    for (int i = 0; i < ties.size(); ++i)
      worst = std::max(worst, std::abs((plus(i) - minus(i)) / (2 * h) - ties.rows()[i].dot(unit)));
  }
  EXPECT_LT(worst, 1e-8);
}

INSTANTIATE_TEST_SUITE_P(PlaneAndSpace, TieRowsTest, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "space" : "plane"; });

}  // namespace
}  // namespace csim
