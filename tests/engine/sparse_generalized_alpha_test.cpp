// The generalized-α stepper's Delassus operator stored by blocks (engine/steppers/
// generalized_alpha_response.h, engine/linear_algebra/block_pattern.h): the same run with W stored sparse
// and dense agrees to the contact solver's tolerance and to the analytical rolling impulses, the sparse W
// stores only the blocks of contacts that share a body, a pile of points (bench/pile_scene.h) carries its
// weight on the box with W by blocks, and the storage keys a stepper cannot honour are refused.
#include "bench/pile_scene.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"
#include "tools/scene/scene_error.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <unistd.h>

namespace csim {
namespace {

std::unique_ptr<Scene> load_text(const std::string& text, std::vector<std::string> overrides) {
  const std::string file = ::testing::TempDir() + "sparse_alpha_" + std::to_string(getpid()) + ".yaml";
  std::ofstream(file) << text;
  std::unique_ptr<Scene> scene;
  try {
    scene = load_scene(file, overrides);
  } catch (...) {
    std::remove(file.c_str());
    throw;
  }
  std::remove(file.c_str());
  return scene;
}

RunReport run_text(const std::string& text, const std::string& storage) {
  return run_scene(*load_text(text, {"contact_solver.storage=" + storage}), {});
}

// Discs of 1 kg and radius 0.1 m, 0.5 m apart on a floor (none touches another), each with the inertia
// (2/5) m R² of a sphere, μ = 0.5, gravity (g_t, −g) = (2.5, −9.81) m/s²: each rolls without slipping
// (g_t = 2.5 m/s² < 3.5 μ g), so every contact's impulse is determined, the floor's normal m g h and its
// friction I/(I + m R²) m g_t h = (2/7) m g_t h against the tilt, and W (2 × 2 blocks, one a disc) is the
// same whichever storage holds it. 30 discs: 60 rows, above the 48 from which `auto` stores by blocks.
constexpr int kDiscs = 30;

std::string rolling_discs(int steps) {
  std::string text = "dimension: 2\ngravity: [2.5, -9.81]\nbodies:\n";
  char line[256];
  for (int k = 0; k < kDiscs; ++k) {
    std::snprintf(line, sizeof line,
                  "  d%d: {type: rigid, mass: 1, inertia: 0.004, position: [%g, 0.1], "
                  "shapes: {disc: {type: sphere, radius: 0.1}}}\n",
                  k, 0.5 * k);
    text += line;
  }
  text += "  floor: {type: fixed, shapes: {surface: {type: halfspace, normal: [0, 1], offset: 0}}}\ncontacts:\n";
  for (int k = 0; k < kDiscs; ++k) {
    std::snprintf(line, sizeof line, "  c%d: {between: [d%d, floor], mu: 0.5}\n", k, k);
    text += line;
  }
  std::snprintf(line, sizeof line,
                "time: {end: %g, step: 1e-3}\nintegrator: {type: generalized-alpha}\n"
                "contact_solver: {tolerance: 1e-8, max_iterations: 20000}\noutput: {rate: 1}\n",
                steps * 1e-3);
  return text + line;
}

TEST(SparseGeneralizedAlpha, AgreesWithTheDenseStorageAndTheRollingImpulses) {
  const int steps = 10;
  const RunReport sparse = run_text(rolling_discs(steps), "sparse");
  const RunReport dense = run_text(rolling_discs(steps), "dense");
  const RunReport automatic = run_text(rolling_discs(steps), "auto");
  EXPECT_EQ(sparse.state.counters.sparse_solves, steps);
  EXPECT_EQ(automatic.state.counters.sparse_solves, steps);  // 60 rows, one disc a block row
  EXPECT_EQ(dense.state.counters.sparse_solves, 0);
  EXPECT_EQ(sparse.state.counters.not_converged + dense.state.counters.not_converged, 0);
  EXPECT_EQ(sparse.state.counters.dense_fallbacks, 0);

  // Impulses (N·s): the solver's tolerance 1e-8 is relative to the free velocity's norm, about
  // g h √(2 · 30); W's diagonal is 1/m to 3.5/m (kg⁻¹): they agree to about 1e-8 · m g h √60 ≈ 1e-9 N·s,
  // 1e-8 relative to m g h. Velocities (m/s) to 1e-8 · g h √60 a step, positions (m) that times t.
  const double g_h = 9.81e-3, t_h = 2.5e-3;
  const std::vector<ActiveContact>&s = sparse.state.contacts, &d = dense.state.contacts;
  ASSERT_EQ(s.size(), static_cast<std::size_t>(kDiscs));
  ASSERT_EQ(d.size(), static_cast<std::size_t>(kDiscs));
  for (std::size_t k = 0; k < s.size(); ++k) {
    ASSERT_TRUE(s[k].point.key == d[k].point.key);
    EXPECT_LE((s[k].impulse - d[k].impulse).norm(), 1e-8 * g_h) << "contact " << k;
    // Rolling (analytical): the floor's normal impulse m g h, its friction (2/7) m g_t h.
    for (const ActiveContact* c : {&s[k], &d[k]}) {
      EXPECT_NEAR(c->impulse(0), g_h, 1e-8 * g_h) << "contact " << k;
      EXPECT_NEAR(std::abs(c->impulse(1)), 2.0 / 7.0 * t_h, 1e-8 * g_h) << "contact " << k;
    }
  }
  const double velocity_tolerance = 1e-8 * g_h * std::sqrt(60.0) * steps;
  EXPECT_LE((sparse.state.v - dense.state.v).lpNorm<Eigen::Infinity>(), velocity_tolerance);
  EXPECT_LE((sparse.state.q - dense.state.q).lpNorm<Eigen::Infinity>(), velocity_tolerance * steps * 1e-3);
  // The centre rolls at (5/7) g_t t: after t = 10 h, (5/7) g_t t to the solver's tolerance.
  const double t = steps * 1e-3;
  for (int k = 0; k < kDiscs; ++k) EXPECT_NEAR(sparse.state.v(3 * k), 5.0 / 7.0 * 2.5 * t, velocity_tolerance) << k;
}

TEST(SparseGeneralizedAlpha, StoresOnlyTheBlocksOfContactsThatShareABody) {
  // Each disc touches the floor only: W is block diagonal (the floor is fixed), 4 entries a contact
  // against the dense storage's m².
  const RunReport sparse = run_text(rolling_discs(2), "sparse");
  const RunReport dense = run_text(rolling_discs(2), "dense");
  const long contacts = static_cast<long>(sparse.state.contacts.size());
  EXPECT_EQ(contacts, kDiscs);
  EXPECT_EQ(dense.state.counters.max_delassus_entries, 4 * contacts * contacts);
  EXPECT_EQ(sparse.state.counters.max_delassus_entries, 4 * contacts);
}

// The pile of bench/pile_scene.h with point masses (generalized_alpha_text): 4 × 4 base, 16 + 9 + 4 = 29 spheres of 1 kg, statically admissible as packed.
std::string point_pile(const std::vector<bench::Sphere>& spheres, int steps) {
  return bench::generalized_alpha_text(bench::scene_text(spheres, 0.1, steps, 4, 4, 0.5, 20000));
}

TEST(SparseGeneralizedAlpha, APileOfPointsCarriesItsWeightWithWByBlocks) {
  const double h = 1e-3, g = 9.81;
  const int steps = 10;
  const std::vector<bench::Sphere> spheres = bench::pile(29, 4, 4, 0.1);
  const RunReport report = run_text(point_pile(spheres, steps), "auto");
  const SolverCounters& counters = report.state.counters;
  EXPECT_EQ(counters.steps, steps);
  EXPECT_EQ(counters.not_converged, 0);
  EXPECT_EQ(counters.sparse_solves, counters.solves);  // every problem stored by blocks

  // Stored: a 3 × 3 block for each pair of contacts sharing a sphere (the box is fixed), itself included;
  // counted on a run of one step (the active set changes over the first steps, the counter is their max).
  const int box = static_cast<int>(spheres.size());
  const RunReport first = run_text(point_pile(spheres, 1), "auto");
  long pairs = 0;
  for (const ActiveContact& a : first.state.contacts)
    for (const ActiveContact& b : first.state.contacts) {
      bool share = false;
      for (int body : {a.body_a, a.body_b})
        share = share || (body != box && (body == b.body_a || body == b.body_b));
      pairs += share ? 1 : 0;
    }
  EXPECT_EQ(first.state.counters.max_delassus_entries, 9 * pairs);
  const std::vector<ActiveContact>& contacts = report.state.contacts;
  EXPECT_LT(counters.max_delassus_entries, 9L * static_cast<long>(contacts.size()) * 20);  // O(contacts)

  // The box carries the pile's weight over the last step: its contacts' vertical impulses on the spheres
  // sum to N m g h, within the spheres' change of momentum over the step (below 2 · 0.01 m g h each).
  double largest_speed = 0.0;
  for (int i = 0; i < report.state.v.size(); ++i) largest_speed = std::max(largest_speed, std::abs(report.state.v(i)));
  EXPECT_LE(largest_speed, 0.01 * g * h);
  double box_impulse = 0.0;
  for (const ActiveContact& contact : contacts) {
    if (contact.body_a != box && contact.body_b != box) continue;
    const ContactPoint& p = contact.point;
    const double up = (contact.impulse(0) * p.normal + contact.impulse(1) * p.t1 + contact.impulse(2) * p.t2).z();
    box_impulse += contact.body_b == box ? -up : up;  // the impulse pushes B along +n, A along −n
  }
  EXPECT_NEAR(box_impulse, spheres.size() * 1.0 * g * h, 0.02 * spheres.size() * g * h);
}

// The key written in the file, so that the refusal is the first answer (an override of a key the file
// leaves to its default is applied after a first reading, which refuses these discs under quasi-static
// for their own reason).
void expect_storage_refused(std::string text, const std::string& integrator, const std::string& storage,
                            const std::string& expected) {
  const std::string solver = "contact_solver: {";
  text.replace(text.find(solver), solver.size(), solver + "storage: " + storage + ", ");
  try {
    load_text(text, {"integrator.type=" + integrator});
    ADD_FAILURE() << integrator << ", storage " << storage << ": expected a refusal";
  } catch (const SceneError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("storage"), std::string::npos) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  }
}

TEST(SparseGeneralizedAlpha, StorageKeysAStepperCannotHonourAreRefused) {
  const std::string discs = rolling_discs(1);
  expect_storage_refused(discs, "ida", "sparse", "use moreau-jean or generalized-alpha");
  expect_storage_refused(discs, "ida-events", "dense", "use moreau-jean or generalized-alpha");
  expect_storage_refused(discs, "quasi-static", "sparse", "use auto or dense");
  for (const std::string storage : {"auto", "dense", "sparse"})
    EXPECT_NO_THROW(load_text(discs, {"contact_solver.storage=" + storage})) << storage;
}

}  // namespace
}  // namespace csim
