// Reduced coordinates of the quasi-static stepper (a ring riding in its hub's frame, a ground whose
// components are prescribed): Φ against its own inverse, T = ∂Φ/∂z and the frame's geometric
// stiffness −Σ f ∂²Φ/∂z² against central finite differences, and the objectivity that motivates the
// floating frame (a hub rotation leaves the strain energy unchanged).
#include "engine/reduced_coordinates.h"
#include "engine/scene/scene.h"

#include <gtest/gtest.h>

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
  SparseMatrix T;
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

TEST(ReducedCoordinates, GeometricStiffnessIsTheSecondDerivativeOfTheFrame) {
  // With K = 0, K_z = −d(Tᵀ f)/dz at a fixed force f.
  const auto scene = coarse_ring();
  const World& world = scene->world;
  const ReducedCoordinates reduced(world, 2.0);
  const Vector z = some_state(reduced, world);
  Vector q, f = Vector::Zero(world.velocity_size);
  for (int i = 0; i < f.size(); ++i) f(i) = std::cos(0.7 * i);
  reduced.expand(z, 2.0, q);
  SparseMatrix T, K_z;
  reduced.tangent(q, T);
  const SparseMatrix zero(world.velocity_size, world.velocity_size);
  reduced.reduce_stiffness(zero, T, q, f, K_z);
  const Matrix analytical(K_z);
  const double h = 1e-6;
  double worst = 0.0, scale = analytical.cwiseAbs().maxCoeff();
  for (int k = 0; k < z.size(); ++k) {
    Vector zp = z, zm = z, qp, qm;
    zp(k) += h;
    zm(k) -= h;
    reduced.expand(zp, 2.0, qp);
    reduced.expand(zm, 2.0, qm);
    SparseMatrix Tp, Tm;
    reduced.tangent(qp, Tp);
    reduced.tangent(qm, Tm);
    const Vector column = -(Tp.transpose() * f - Tm.transpose() * f) / (2 * h);
    worst = std::max(worst, (column - analytical.col(k)).lpNorm<Eigen::Infinity>());
  }
  ASSERT_GT(scale, 0.1);
  EXPECT_LT(worst, 1e-7 * scale);
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

}  // namespace
}  // namespace csim
