// The contact stage's sparse Delassus operator (engine/contact_stage/forward_columns.h, block_gram.h) on a
// pile of rigid spheres packed in a box (bench/pile_scene.h): the stage stores W by blocks, and the
// packing, statically admissible, stays at rest, its weight carried by the floor.
#include "bench/pile_scene.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <unistd.h>

namespace csim {
namespace {

TEST(SparseContactStage, APackedPileStaysAtRestWithItsWeightOnTheFloor) {
  // A 4 × 4 base, 16 + 9 + 4 = 29 spheres of 1 kg: 16 floor, 16 wall, 40 lateral and 52 support contacts
  // once settled (372 rows), far above the 48 rows from which the stage stores W by blocks.
  const double radius = 0.1, h = 1e-3;
  const int steps = 10;
  const std::vector<bench::Sphere> spheres = bench::pile(29, 4, 4, radius);
  const std::string file = ::testing::TempDir() + "sparse_pile_" + std::to_string(getpid()) + ".yaml";
  std::ofstream(file) << bench::scene_text(spheres, radius, steps, 4, 4, 0.5, 20000);
  const std::unique_ptr<Scene> scene = load_scene(file, {});
  std::remove(file.c_str());
  const RunReport report = run_scene(*scene, {});

  const SolverCounters& counters = report.state.counters;
  EXPECT_EQ(counters.steps, steps);
  EXPECT_EQ(counters.not_converged, 0);
  EXPECT_EQ(counters.sparse_solves, counters.solves);  // every problem stored by blocks
  EXPECT_EQ(counters.solves, steps);

  // At rest: no sphere moved by more than 2e-4 R (an upper sphere falls g h² before its supports' contacts,
  // whose relative velocity is zero in free fall, activate: 1e-4 R), or has a speed above g h / 100.
  const double g = 9.81;
  double largest_speed = 0.0;
  for (int i = 0; i < report.state.v.size(); ++i) largest_speed = std::max(largest_speed, std::abs(report.state.v(i)));
  EXPECT_LE(largest_speed, 0.01 * g * h);
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    EXPECT_NEAR(report.state.q(7 * k + 0), spheres[k].x, 2e-4 * radius) << "sphere " << k;
    EXPECT_NEAR(report.state.q(7 * k + 1), spheres[k].y, 2e-4 * radius) << "sphere " << k;
    EXPECT_NEAR(report.state.q(7 * k + 2), spheres[k].z, 2e-4 * radius) << "sphere " << k;
  }
  // The floor's normal impulses carry the pile's weight over the last step: Σ r_n = m g h (the walls'
  // normals are horizontal, and the spheres do not accelerate).
  double floor_impulse = 0.0;
  for (const ActiveContact& contact : report.state.contacts)
    if (std::abs(contact.point.normal.z()) > 0.5 && std::min(contact.point.point_a.z(), contact.point.point_b.z()) < 0.5 * radius)
      floor_impulse += contact.impulse(0);
  EXPECT_NEAR(floor_impulse, spheres.size() * 1.0 * g * h, 1e-6 * spheres.size() * g * h);
}

}  // namespace
}  // namespace csim
