// Reduced coordinates of the quasi-static stepper (a ring riding in its hub's frame, a ground whose
// components are prescribed): Φ against its own inverse, T = ∂Φ/∂z and the frame's geometric
// stiffness −Σ f ∂²Φ/∂z² against central finite differences, and the objectivity that motivates the
// floating frame (a hub rotation leaves the strain energy unchanged); the same in 3D, where the hub's
// rotation and the ground's are quaternions moved by increments, and the 3D ring held in z rolls as
// the plane one; the frame's reduction of the stiffness (a ring evaluated in its hub's frame) against
// the world's sparse product; a tangent written over the last one is a new one, bit for bit.
#include "engine/reduced_coordinates.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

namespace csim {
namespace {

const std::string kRing = CSIM_SOURCE_DIR "/scenes/rolling-ring/scene.yaml";

std::unique_ptr<Scene> coarse_ring() {
  return load_scene(kRing, {"parameters.divisions_circumferential=8", "parameters.divisions_radial=2",
                            "parameters.material=linear-elastic"});
}

// A state away from the reference: every unknown perturbed, the hub turned by 0.7 rad.
Vector some_state(const ReducedCoordinates& reduced, const World& world) {
  Vector z = Vector::Zero(reduced.size());
  for (int k = 0; k < z.size(); ++k) z(k) = 0.01 * std::sin(1.3 * k + 0.2);
  const int hub = world.bodies[world.body_index("hub")].position_offset;
  z(reduced.unknown(hub + 2)) = 0.7;
  return z;
}

TEST(ReducedCoordinates, UnknownsAreTheFreeComponents) {
  const auto scene = coarse_ring();
  const World& world = scene->world;
  const ReducedCoordinates reduced(world, 2.0);  // after the press: the hub's spin is released
  const int hub = world.bodies[world.body_index("hub")].position_offset;
  EXPECT_LT(reduced.unknown(hub), 0);      // x, y held
  EXPECT_GE(reduced.unknown(hub + 2), 0);  // spin free
  EXPECT_TRUE(reduced.prescribed(world.bodies[world.body_index("ground")].position_offset));
  // ring: 2 × (9 × 3 nodes) minus the 9 tied inner nodes' 18; hub: 1
  EXPECT_EQ(reduced.size(), 2 * 8 * 3 - 2 * 8 + 1);
  const ReducedCoordinates pressing(world, 0.5);  // spin held during the press
  EXPECT_EQ(pressing.size(), reduced.size() - 1);
}

TEST(ReducedCoordinates, GatherInvertsExpand) {
  const auto scene = coarse_ring();
  ReducedCoordinates reduced(scene->world, 2.0);
  const Vector z = some_state(reduced, scene->world);
  Vector q, z_back;
  reduced.expand(z, 2.0, q);
  reduced.gather(q, 2.0, z_back);
  EXPECT_LT((z_back - z).lpNorm<Eigen::Infinity>(), 1e-14);
}

TEST(ReducedCoordinates, TangentMatchesFiniteDifferences) {
  const auto scene = coarse_ring();
  const ReducedCoordinates reduced(scene->world, 2.0);
  const Vector z = some_state(reduced, scene->world);
  Vector q, q_plus, q_minus;
  reduced.expand(z, 2.0, q);
  SparseRowMatrix T;
  reduced.tangent(q, T);
  const Matrix dense(T);
  const double h = 1e-6;
  double worst = 0.0;
  for (int k = 0; k < z.size(); ++k) {
    Vector zp = z, zm = z;
    zp(k) += h;
    zm(k) -= h;
    reduced.expand(zp, 2.0, q_plus);
    reduced.expand(zm, 2.0, q_minus);
    worst = std::max(worst, ((q_plus - q_minus) / (2 * h) - dense.col(k)).lpNorm<Eigen::Infinity>());
  }
  EXPECT_LT(worst, 1e-9);
}

// Whether two sparse matrices have the same pattern and the same values to the bit.
bool same_bits(const SparseRowMatrix& a, const SparseRowMatrix& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && a.nonZeros() == b.nonZeros() &&
         std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.outerSize() + 1, b.outerIndexPtr()) &&
         std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr()) &&
         std::memcmp(a.valuePtr(), b.valuePtr(), sizeof(double) * static_cast<std::size_t>(a.nonZeros())) == 0;
}

TEST(ReducedCoordinates, ATangentWrittenOverTheLastIsANewOne) {
  // T is written in place while its pattern stays (reduced_coordinates.cpp): at another state, with the
  // hub at its reference, and for other unknowns (the press), the same matrix as a new one, bit for bit.
  const auto scene = coarse_ring();
  const World& world = scene->world;
  const ReducedCoordinates rolling(world, 2.0), pressing(world, 0.5);
  Vector q;
  SparseRowMatrix T;
  const auto expect_new = [&](const ReducedCoordinates& reduced, const Vector& z) {
    reduced.expand(z, 2.0, q);
    SparseRowMatrix fresh;
    reduced.tangent(q, fresh);
    reduced.tangent(q, T);
    EXPECT_TRUE(same_bits(T, fresh));
  };
  const Vector z = some_state(rolling, world);
  expect_new(rolling, z);
  expect_new(rolling, 0.5 * z);
  expect_new(rolling, Vector::Zero(rolling.size()));
  expect_new(pressing, Vector::Constant(pressing.size(), 0.01));
  expect_new(rolling, z);
}

TEST(ReducedCoordinates, GeometricStiffnessIsTheSecondDerivativeOfTheFrame) {
  // With K = 0, K_z = −d(Tᵀ f)/dz at a fixed force f.
  const auto scene = coarse_ring();
  const World& world = scene->world;
  ReducedCoordinates reduced(world, 2.0);
  const Vector z = some_state(reduced, world);
  Vector q, f = Vector::Zero(world.velocity_size);
  for (int i = 0; i < f.size(); ++i) f(i) = std::cos(0.7 * i);
  reduced.expand(z, 2.0, q);
  SparseRowMatrix T;
  SparseMatrix K_z;
  reduced.tangent(q, T);
  reduced.reduce_stiffness(q, f, Triplets{}, 0, K_z);
  const Matrix analytical(K_z);
  const double h = 1e-6;
  double worst = 0.0, scale = analytical.cwiseAbs().maxCoeff();
  for (int k = 0; k < z.size(); ++k) {
    Vector zp = z, zm = z, qp, qm;
    zp(k) += h;
    zm(k) -= h;
    reduced.expand(zp, 2.0, qp);
    reduced.expand(zm, 2.0, qm);
    SparseRowMatrix Tp, Tm;
    reduced.tangent(qp, Tp);
    reduced.tangent(qm, Tm);
    const Vector column = -(Tp.transpose() * f - Tm.transpose() * f) / (2 * h);
    worst = std::max(worst, (column - analytical.col(k)).lpNorm<Eigen::Infinity>());
  }
  ASSERT_GT(scale, 0.1);
  EXPECT_LT(worst, 1e-7 * scale);
}

// The ring evaluated in its hub's frame, its force turned to the world and its tangent reduced by
// reduce_stiffness, against the same ring evaluated at q in the world and reduced by the general sparse
// product Tᵀ K T + G. Some world-frame entries (a spring's: symmetric, and one not) join a node of the ring
// to another and to the hub, so that the turning of world entries is exercised too.
void expect_frame_reduction_equals_the_world_product(ReducedCoordinates& reduced, const World& world,
                                                     const Vector& q) {
  const int ring_index = world.body_index("ring");
  const BodyInstance& ring = world.bodies[ring_index];
  ASSERT_TRUE(reduced.floats(ring_index));
  const int n = world.velocity_size, size = ring.body->velocity_size();
  Vector f_world = Vector::Zero(n), frame_force = Vector::Zero(size), f_frame = Vector::Zero(n), positions;
  Triplets world_entries, frame_entries;
  ring.body->add_internal_force_and_tangent(ring.positions(q), f_world.segment(ring.velocity_offset, size),
                                            ring.velocity_offset, world_entries);
  reduced.frame_positions(q, ring_index, positions);
  ring.body->add_internal_force_and_tangent(positions, frame_force, ring.velocity_offset, frame_entries);
  reduced.add_turned_to_world(q, ring_index, frame_force, f_frame.segment(ring.velocity_offset, size));
  const double force_scale = f_world.lpNorm<Eigen::Infinity>();
  ASSERT_GT(force_scale, 0.0);
  EXPECT_LT((f_frame - f_world).lpNorm<Eigen::Infinity>(), 1e-10 * force_scale);

  const std::size_t world_from = frame_entries.size();
  const int a = ring.velocity_offset + size - 1, b = ring.velocity_offset + size / 2;  // free nodes' components
  const int hub = world.bodies[world.body_index("hub")].velocity_offset + (world.dimension == 2 ? 2 : 5);
  const Triplets extra = {{a, a, 300.0}, {a, b, -300.0}, {b, a, -300.0}, {b, b, 300.0}, {a, hub, 70.0}};
  for (const auto& t : extra) {
    world_entries.push_back(t);
    frame_entries.push_back(t);
  }
  SparseMatrix K(n, n), G, K_z;
  K.setFromTriplets(world_entries.begin(), world_entries.end());
  SparseRowMatrix T;
  reduced.tangent(q, T);
  const SparseMatrix T_columns = T;
  Matrix expected = Matrix(SparseMatrix(T_columns.transpose() * K * T_columns));
  if (reduced.geometric_stiffness(q, f_world, G)) expected += Matrix(G);
  reduced.reduce_stiffness(q, f_world, frame_entries, world_from, K_z);
  const double scale = expected.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 1.0);
  EXPECT_LT((Matrix(K_z) - expected).cwiseAbs().maxCoeff(), 1e-11 * scale);
}

TEST(ReducedCoordinates, TheFrameReductionIsTheWorldProduct) {
  const auto scene = load_scene(kRing, {"parameters.divisions_circumferential=8", "parameters.divisions_radial=2",
                                        "parameters.material=mooney-rivlin"});
  ReducedCoordinates reduced(scene->world, 2.0);
  Vector q;
  reduced.expand(some_state(reduced, scene->world), 2.0, q);
  expect_frame_reduction_equals_the_world_product(reduced, scene->world, q);
}

TEST(ReducedCoordinates, TurningTheHubLeavesTheStrainEnergyUnchanged) {
  // The floating frame: the same w at any hub angle is the same strain state (finite strain is
  // objective), so the energy does not depend on the angle.
  const auto scene = coarse_ring();
  const World& world = scene->world;
  const ReducedCoordinates reduced(world, 2.0);
  Vector z = some_state(reduced, world), q;
  const BodyInstance& ring = world.bodies[world.body_index("ring")];
  const int spin = reduced.unknown(world.bodies[world.body_index("hub")].position_offset + 2);
  z(spin) = 0.0;
  reduced.expand(z, 2.0, q);
  const double energy = ring.body->strain_energy(ring.positions(q));
  ASSERT_GT(energy, 0.0);
  for (double angle : {0.3, 1.5, 3.0, -2.0}) {
    z(spin) = angle;
    reduced.expand(z, 2.0, q);
    EXPECT_NEAR(ring.body->strain_energy(ring.positions(q)), energy, 1e-11 * energy) << angle;
  }
}

// ----- 3D: a HEXA8 ring held in z on a 3D hub, a ground turning about a vertical axis -----------------

const std::string kRing3d = CSIM_SOURCE_DIR "/scenes/rolling-ring-3d/scene.yaml";

std::unique_ptr<Scene> coarse_ring_3d(std::vector<std::string> overrides = {}) {
  overrides.insert(overrides.end(), {"parameters.divisions_circumferential=8", "parameters.divisions_radial=2",
                                     "parameters.inner_radius=1.0"});
  return load_scene(kRing3d, overrides);
}

Vector initial_positions(const World& world) {
  Vector q(world.position_size);
  for (const BodyInstance& b : world.bodies) q.segment(b.position_offset, b.body->position_size()) = b.initial_position;
  return q;
}

// A state away from the reference, gathered again so that it is the base (3D rotations: zero increments).
Vector some_state_3d(ReducedCoordinates& reduced, const World& world, double t, Vector& q) {
  Vector z;
  reduced.gather(initial_positions(world), 0.0, z);
  for (int k = 0; k < z.size(); ++k) z(k) += 0.01 * std::sin(1.3 * k + 0.2);
  z(reduced.unknown(world.bodies[world.body_index("hub")].velocity_offset + 5)) = 0.7;
  reduced.expand(z, t, q);
  reduced.gather(q, t, z);
  return z;
}

TEST(ReducedCoordinates3d, UnknownsAreTheFreeComponents) {
  const auto scene = coarse_ring_3d();
  const World& world = scene->world;
  const ReducedCoordinates reduced(world, 2.0);
  const int hub = world.bodies[world.body_index("hub")].velocity_offset;
  for (int c = 0; c < 5; ++c) EXPECT_LT(reduced.unknown(hub + c), 0) << c;  // held
  EXPECT_GE(reduced.unknown(hub + 5), 0);                                      // spin free
  // ring: 8 × 3 × 2 nodes, z held on all, the 16 inner ones tied: 32 free nodes × (x, y); hub: 1
  EXPECT_EQ(reduced.size(), 2 * 32 + 1);
}

TEST(ReducedCoordinates3d, GatherInvertsExpand) {
  const auto scene = coarse_ring_3d();
  ReducedCoordinates reduced(scene->world, 2.0);
  Vector q, q_back;
  const Vector z = some_state_3d(reduced, scene->world, 2.0, q);
  reduced.expand(z, 2.0, q_back);
  EXPECT_LT((q_back - q).lpNorm<Eigen::Infinity>(), 1e-14);
}

TEST(ReducedCoordinates3d, TangentAndGeometricStiffnessMatchFiniteDifferences) {
  const auto scene = coarse_ring_3d();
  const World& world = scene->world;
  ReducedCoordinates reduced(world, 2.0);
  Vector q;
  const Vector z = some_state_3d(reduced, world, 2.0, q);
  SparseRowMatrix T;
  SparseMatrix K_z;
  reduced.tangent(q, T);
  Vector f(world.velocity_size);
  for (int i = 0; i < f.size(); ++i) f(i) = std::cos(0.7 * i);
  reduced.reduce_stiffness(q, f, Triplets{}, 0, K_z);
  const Matrix tangent(T), stiffness(K_z);
  const double h = 1e-6, scale = stiffness.cwiseAbs().maxCoeff();
  double worst_tangent = 0.0, worst_stiffness = 0.0;
  for (int k = 0; k < z.size(); ++k) {
    Vector zp = z, zm = z, qp, qm, dq_plus, dq_minus;
    zp(k) += h;
    zm(k) -= h;
    reduced.expand(zp, 2.0, qp);
    reduced.expand(zm, 2.0, qm);
    world.position_difference(qp, q, dq_plus);  // velocity components (the hub's rotation is a quaternion)
    world.position_difference(qm, q, dq_minus);
    worst_tangent = std::max(worst_tangent, ((dq_plus - dq_minus) / (2 * h) - tangent.col(k)).lpNorm<Eigen::Infinity>());
    SparseRowMatrix Tp, Tm;
    reduced.tangent(qp, Tp);
    reduced.tangent(qm, Tm);
    const Vector column = -(Tp.transpose() * f - Tm.transpose() * f) / (2 * h);
    worst_stiffness = std::max(worst_stiffness, (column - stiffness.col(k)).lpNorm<Eigen::Infinity>());
  }
  EXPECT_LT(worst_tangent, 1e-8);
  ASSERT_GT(scale, 0.1);
  EXPECT_LT(worst_stiffness, 1e-7 * scale);
}

TEST(ReducedCoordinates3d, TheFrameReductionIsTheWorldProduct) {
  const auto scene = coarse_ring_3d();
  ReducedCoordinates reduced(scene->world, 2.0);
  Vector q;
  some_state_3d(reduced, scene->world, 2.0, q);
  expect_frame_reduction_equals_the_world_product(reduced, scene->world, q);
}

TEST(ReducedCoordinates3d, TurningTheHubLeavesTheStrainEnergyUnchanged) {
  const auto scene = coarse_ring_3d();
  const World& world = scene->world;
  ReducedCoordinates reduced(world, 2.0);
  Vector q;
  Vector z = some_state_3d(reduced, world, 2.0, q);
  const BodyInstance& ring = world.bodies[world.body_index("ring")];
  const double energy = ring.body->strain_energy(ring.positions(q));
  ASSERT_GT(energy, 0.0);
  const int spin = reduced.unknown(world.bodies[world.body_index("hub")].velocity_offset + 5);
  for (double angle : {0.3, 1.5, 3.0, -2.0}) {
    z(spin) = angle;
    reduced.expand(z, 2.0, q);
    EXPECT_NEAR(ring.body->strain_energy(ring.positions(q)), energy, 1e-11 * energy) << angle;
  }
}

TEST(ReducedCoordinates3d, TheGroundTurnsAboutItsVerticalAxisAsPrescribed) {
  // Cornering: the ground turns by Omega (t - t_roll), Omega = v / R_c = 0.02 rad/s, t_roll = 1.2 s,
  // about its vertical axis through (0, ., -R_c), from any base; its translation is absolute (the base
  // here is the initial state, before the press).
  const auto scene = coarse_ring_3d();
  const World& world = scene->world;
  ReducedCoordinates reduced(world, 2.0);
  const BodyInstance& ground = world.bodies[world.body_index("ground")];
  Vector z, q = initial_positions(world), next;
  double base_time = 1.2;
  for (double t : {2.7, 4.2}) {
    reduced.gather(q, base_time, z);
    reduced.expand(z, t, next);
    const Eigen::Isometry3d pose = ground.body->pose(ground.positions(next));
    const Eigen::Matrix3d expected = Eigen::AngleAxisd(0.02 * (t - 1.2), Eigen::Vector3d::UnitY()).toRotationMatrix();
    EXPECT_LT((pose.linear() - expected).cwiseAbs().maxCoeff(), 1e-14) << t;
    EXPECT_LT((pose.translation() - Eigen::Vector3d(0.0, -2.5 + 0.05, -100.0)).norm(), 1e-14) << t;
    q = next;
    base_time = t;
  }
}

TEST(RollingRing3d, HeldInZItRollsLikeThePlaneRing) {
  // The plane-strain HEXA8 ring, straight rolling: the same equilibrium as the quad4 ring of the plane
  // scene (a HEXA8 with z held on both faces is the plane-strain quad4, mean dilatation included).
  const std::vector<std::string> common = {
      "parameters.divisions_circumferential=16", "parameters.divisions_radial=3", "parameters.inner_radius=1.0",
      "parameters.indentation=0.1", "parameters.mu=0.2", "parameters.material=mooney-rivlin",
      "parameters.roll_time=0.6", "parameters.window=0.3"};
  auto plane = load_scene(kRing, common);
  std::vector<std::string> spatial = common;
  spatial.push_back("parameters.cornering_radius=0");
  auto space = load_scene(kRing3d, spatial);
  const RunReport a = run_scene(*plane, {}), b = run_scene(*space, {});
  const auto spin = [](const Scene& scene, const RunReport& report) {
    const int hub = scene.world.body_index("hub");
    const BodyInstance& body = scene.world.bodies[hub];
    return report.state.v(body.velocity_offset + body.body->velocity_size() - 1);
  };
  const double plane_spin = spin(*plane, a), space_spin = spin(*space, b);
  ASSERT_GT(plane_spin, 0.5);  // rolling (v / R = 1)
  // Both are Newton iterates within the tolerance 1e-9 · R = 2e-9 of the same equilibrium, whose spin
  // is Δθ / h with h = 0.01: they may differ by 2 · 2e-9 / 0.01 = 4e-7 (v / R = 1).
  EXPECT_NEAR(space_spin, plane_spin, 4e-7);
}

}  // namespace
}  // namespace csim
