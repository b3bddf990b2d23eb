// The contact stage's sparse Delassus operator (engine/contact_stage/forward_columns.h, block_gram.h) on
// rigid spheres packed in a box (bench/pile_scene.h): the same run with W stored sparse and dense agrees
// to the contact solver's tolerance, the sparse W stores only the blocks of contacts that share a body,
// and a packed pile, statically admissible, stays at rest with its weight on the floor, every touching
// pair in the problem at every step (the stage's touching band, contact_stage.h).
#include "bench/pile_scene.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <unistd.h>

namespace csim {
namespace {

RunReport run_text(const std::string& text, const std::string& storage) {
  const std::string file = ::testing::TempDir() + "sparse_pile_" + std::to_string(getpid()) + ".yaml";
  std::ofstream(file) << text;
  const std::unique_ptr<Scene> scene = load_scene(file, {"contact_solver.storage=" + storage});
  std::remove(file.c_str());
  return run_scene(*scene, {});
}

// Spheres of 1 kg and radius 0.1 m on the floor of a 9 × 8 box, on the black squares of its base's grid
// away from the east and north walls (none touches another), μ = 0.5, gravity tilted towards those walls:
// each sphere rolls without slipping (g_t = 2.5 m/s² < 3.5 μ g_z), so every contact's impulse is determined
// (the floor's normal m g_z h, its friction (2/7) m g_t h opposing the tilt) and W is the same whichever
// storage holds it.
std::string rolling_scene(int steps) {
  std::vector<bench::Sphere> spheres;
  for (const bench::Sphere& s : bench::pile(72, 9, 8, 0.1))
    if (s.i < 8 && s.j < 7 && (s.i + s.j) % 2 == 0) spheres.push_back(s);
  std::string text = bench::scene_text(spheres, 0.1, steps, 9, 8, 0.5, 20000);
  const std::string vertical = "gravity: [0, 0, -9.81]";
  text.replace(text.find(vertical), vertical.size(), "gravity: [2, 1.5, -9.81]");
  return text;
}

TEST(SparseContactStage, AgreesWithTheDenseStageToTheSolversTolerance) {
  const int steps = 10;
  const RunReport sparse = run_text(rolling_scene(steps), "sparse");
  const RunReport dense = run_text(rolling_scene(steps), "dense");
  EXPECT_EQ(sparse.state.counters.sparse_solves, steps);
  EXPECT_EQ(dense.state.counters.sparse_solves, 0);
  EXPECT_EQ(sparse.state.counters.not_converged + dense.state.counters.not_converged, 0);
  EXPECT_EQ(sparse.state.counters.dense_fallbacks, 0);

  // Impulses: the solver's tolerance 1e-8 is relative to the free velocity's norm, about g h √(3 · 28)
  // (m/s); W's diagonal is 1/m to 3.5/m (kg⁻¹), so the impulses agree to about 1e-8 · m g h √84, 1e-9
  // N·s: 1e-8 N·s leaves a margin. Velocities (m/s) to 1e-8 · g h √84 · 10 likewise.
  const double g_h = 9.81e-3, t_h = 2.5e-3;
  const std::vector<ActiveContact>&s = sparse.state.contacts, &d = dense.state.contacts;
  // 28 on the floor, and 8 rows of the west and south walls that the spheres beside them roll away
  // from (every inelastic candidate is a row, moreau_jean.h step 2): those carry nothing.
  ASSERT_EQ(s.size(), 36u);
  ASSERT_EQ(d.size(), 36u);
  int on_floor = 0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    ASSERT_TRUE(s[k].point.key == d[k].point.key);
    EXPECT_LE((s[k].impulse - d[k].impulse).norm(), 1e-8) << "contact " << k;
    if (std::abs(d[k].point.normal.z()) < 0.5) {
      EXPECT_EQ(d[k].impulse.norm(), 0.0) << "contact " << k;
      continue;
    }
    ++on_floor;
    // Rolling: the floor's normal impulse m g_z h, its friction (2/7) m g_t h (analytical).
    EXPECT_NEAR(d[k].impulse(0), g_h, 1e-8) << "contact " << k;
    EXPECT_NEAR(d[k].impulse.tail<2>().norm(), 2.0 / 7.0 * t_h, 1e-8) << "contact " << k;
  }
  EXPECT_EQ(on_floor, 28);
  EXPECT_LE((sparse.state.v - dense.state.v).lpNorm<Eigen::Infinity>(), 1e-8 * g_h * std::sqrt(84.0) * 10);
  EXPECT_LE((sparse.state.q - dense.state.q).lpNorm<Eigen::Infinity>(), 1e-8 * g_h * std::sqrt(84.0) * 10 * steps * 1e-3);
}

TEST(SparseContactStage, StoresOnlyTheBlocksOfContactsThatShareABody) {
  // No two spheres touch, and the floor and walls are fixed: two contacts share a body only when they
  // are the same sphere's (its floor and a wall beside it), so W stores, for each sphere with n contacts,
  // n² blocks of 9 entries, against the dense storage's m².
  const RunReport sparse = run_text(rolling_scene(2), "sparse");
  const RunReport dense = run_text(rolling_scene(2), "dense");
  const std::vector<ActiveContact>& contacts = sparse.state.contacts;
  const long m = 3 * static_cast<long>(contacts.size());
  std::map<int, long> per_sphere;
  for (const ActiveContact& c : contacts) ++per_sphere[std::min(c.body_a, c.body_b)];  // the box comes last
  long blocks = 0;
  for (const auto& [body, n] : per_sphere) blocks += n * n;
  EXPECT_GT(blocks, static_cast<long>(contacts.size()));  // some sphere has a wall row beside its floor's
  EXPECT_EQ(dense.state.counters.max_delassus_entries, m * m);
  EXPECT_EQ(sparse.state.counters.max_delassus_entries, 9 * blocks);
}

TEST(SparseContactStage, APackedPileStaysAtRestWithItsWeightOnTheFloor) {
  // A 4 × 4 base, 16 + 9 + 4 = 29 spheres of 1 kg: 16 floor, 16 wall, 40 lateral and 52 support contacts
  // once settled (372 rows), far above the rows from which the stage stores W by blocks. The sparse
  // solver may stall on this hyperstatic stack; the stage then solves it dense (contact_solve.h): either
  // way every solve converges.
  const double radius = 0.1, h = 1e-3;
  const int steps = 10;
  const std::vector<bench::Sphere> spheres = bench::pile(29, 4, 4, radius);
  const RunReport report = run_text(bench::scene_text(spheres, radius, steps, 4, 4, 0.5, 20000), "auto");

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
  // The box (floor and walls, body spheres.size()) carries the pile's weight over the last step: the
  // vertical components of its contacts' impulses on the spheres sum to m g h (the walls' friction takes
  // part of it), within the spheres' change of momentum over the step (each below 2 · 0.01 m g h above).
  const int box = static_cast<int>(spheres.size());
  double box_impulse = 0.0;
  for (const ActiveContact& contact : report.state.contacts) {
    if (contact.body_a != box && contact.body_b != box) continue;
    const ContactPoint& p = contact.point;
    const double up = (contact.impulse(0) * p.normal + contact.impulse(1) * p.t1 + contact.impulse(2) * p.t2).z();
    box_impulse += contact.body_b == box ? -up : up;  // the impulse pushes B along +n, A along −n
  }
  EXPECT_NEAR(box_impulse, spheres.size() * 1.0 * g * h, 0.02 * spheres.size() * g * h);
}

TEST(SparseContactStage, APackedPileKeepsEveryTouchingPairInItsProblem) {
  // Two layers on a 9 × 8 base (72 + 28 spheres): every pair the packing makes touch is at a gap of
  // round-off, and the sideways contacts of the base hold the upper layer's thrust. Counted from the
  // geometry: each base sphere on the floor, the base's outer ones on the walls, and every two spheres
  // whose centres are 2R apart. Each of those must be in the problem at the end (the band keeps them,
  // where "closed" as gap ≤ 0 let round-off drop and re-admit them from step to step: 296 of the 390
  // were left after 10 steps, and the pile moved), every solve converged, the pile at rest.
  const double radius = 0.1, h = 1e-3;
  const int steps = 30;
  const std::vector<bench::Sphere> spheres = bench::pile(100, 9, 8, radius);
  const RunReport report = run_text(bench::scene_text(spheres, radius, steps, 9, 8, 0.5, 20000), "sparse");

  std::size_t touching = 0;
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    const bench::Sphere& p = spheres[k];
    if (p.layer == 0) touching += 1 + (p.i == 0) + (p.i == 8) + (p.j == 0) + (p.j == 7);  // floor, walls
    for (std::size_t l = k + 1; l < spheres.size(); ++l) {
      const bench::Sphere& q = spheres[l];
      const double distance = std::sqrt((p.x - q.x) * (p.x - q.x) + (p.y - q.y) * (p.y - q.y) + (p.z - q.z) * (p.z - q.z));
      if (std::abs(distance - 2.0 * radius) <= 1e-12 * radius) ++touching;
    }
  }
  ASSERT_EQ(touching, 390u);  // 72 floor, 34 wall, 127 + 45 in the layers, 4 × 28 supports
  const SolverCounters& counters = report.state.counters;
  EXPECT_EQ(counters.steps, steps);
  EXPECT_EQ(counters.not_converged, 0);
  EXPECT_EQ(report.state.contacts.size(), touching);
  const double g = 9.81;
  EXPECT_LE(report.state.v.lpNorm<Eigen::Infinity>(), 0.01 * g * h);
}

TEST(SparseContactStage, ASettledPileIsSolvedFromItsWarmStartAtEveryStep) {
  // The full 200-sphere pile (4 layers, 962 contacts) over 60 steps. Two things kept the warm start from
  // solving it: tangent frames chosen at ties by round-off (t1 turned by 90° between steps, the stored
  // friction impulses then pointed the wrong way: |ΔW|/|W| = 0.4–0.9 a step, 100–200 sweeps a solve),
  // and the gap-closing term on round-off gaps, which left the problem without a solution below 1e-8
  // after about 30 steps (20 000 sweeps, unconverged). A solve from the last step's impulses now takes a
  // sweep or two; the first, from zero, about 170. Bound: 10 a solve on average, the pile at rest.
  const double radius = 0.1, h = 1e-3;
  const int steps = 60;
  const std::vector<bench::Sphere> spheres = bench::pile(200, 9, 8, radius);
  const RunReport report = run_text(bench::scene_text(spheres, radius, steps, 9, 8, 0.5, 20000), "sparse");
  const SolverCounters& counters = report.state.counters;
  EXPECT_EQ(counters.steps, steps);
  EXPECT_EQ(counters.not_converged, 0);
  EXPECT_EQ(counters.dense_fallbacks, 0);
  EXPECT_LE(counters.total_iterations, 10 * counters.solves);
  const double g = 9.81;
  EXPECT_LE(report.state.v.lpNorm<Eigen::Infinity>(), 0.01 * g * h);
  // Nothing sinks into anything: the deepest overlap of an active contact at a step's start is
  // round-off (2.3e-13 m measured), below the touching band, 1e-9 of the largest bounding radius.
  EXPECT_LE(counters.deepest_penetration, 1e-9 * radius);
}

}  // namespace
}  // namespace csim
