// A settled pile of rigid spheres: the cost of a Moreau–Jean step with a few hundred frictional contacts
// between many bodies (run by hand: build/bench/bench_pile [spheres] [steps] [repeats] [auto|dense|sparse]
// [moreau-jean|generalized-alpha] [sleep speed, m/s]).
//
// The pile (bench/pile_scene.h): spheres packed in a box, settled by construction; a 9 × 8 base gives
// 72 + 56 + 42 + 30 = 200 spheres in four layers, other counts fill the layers in order. Each sphere
// touches the floor or four below it, its neighbours in its layer, and the walls for the base's outer
// ones: a few nonzero 3 × 3 blocks a row of W, the sparsity of a physics-engine scene, and a hyperstatic
// stack, the hard case of Gauss–Seidel. μ = 0.5, gravity 9.81, h = 1e-3, θ = ½, the contact solver's
// tolerance 1e-8 and at most 20 000 sweeps. Printed: the spheres, the contacts of the last step, ms per
// step (median and min–max over the repeats) with the stepper's phase timers of the last repeat, or
// where the contact solver stopped the run.
// With a sleep speed (Moreau–Jean): integrator.sleep_speed at that value and sleep_time 0.05 s, so that
// the pile, at rest from the start, falls asleep after 50 steps (engine/steppers/sleeping_islands.h);
// printed also the bodies asleep at the end.
// generalized-alpha: the same pile of point masses (pile_scene.h), ρ∞ = 0.8, its W from its own response
// (engine/steppers/generalized_alpha_response.h).
#include "bench/pile_scene.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

int main(int argc, char** argv) {
  const int count = argc > 1 ? std::atoi(argv[1]) : 200;
  const int steps = argc > 2 ? std::atoi(argv[2]) : 5;
  const int repeats = argc > 3 ? std::atoi(argv[3]) : 3;
  const std::string storage = argc > 4 ? argv[4] : "auto";  // contact_solver.storage: auto, dense or sparse
  const std::string integrator = argc > 5 ? argv[5] : "moreau-jean";
  const std::string sleep_speed = argc > 6 ? argv[6] : "0";
  if (integrator != "moreau-jean" && integrator != "generalized-alpha") {
    std::printf("integrator: moreau-jean or generalized-alpha, not '%s'\n", integrator.c_str());
    return 2;
  }
  const double radius = 0.1;
  const std::vector<csim::bench::Sphere> spheres = csim::bench::pile(count, 9, 8, radius);
  const std::string file = "/tmp/bench_pile_" + std::to_string(getpid()) + ".yaml";
  std::string text = csim::bench::scene_text(spheres, radius, steps, 9, 8);
  if (integrator == "generalized-alpha") text = csim::bench::generalized_alpha_text(text);
  std::ofstream(file) << text;
  std::vector<std::string> overrides{"contact_solver.storage=" + storage};
  if (sleep_speed != "0") overrides.insert(overrides.end(), {"integrator.sleep_speed=" + sleep_speed, "integrator.sleep_time=0.05"});
  const std::unique_ptr<csim::Scene> scene = csim::load_scene(file, overrides);
  std::remove(file.c_str());

  std::vector<double> ms;
  csim::RunReport report;
  for (int k = 0; k < repeats; ++k) {
    try {
      report = csim::run_scene(*scene, {});
    } catch (const std::exception& error) {
      std::printf("%zu spheres: the run stopped: %s\n", spheres.size(), error.what());
      return 1;
    }
    ms.push_back(1e3 * report.wall_time / static_cast<double>(report.state.counters.steps));
  }
  std::sort(ms.begin(), ms.end());
  const csim::PhaseTimers& t = report.state.timers;
  const double per = 1e3 / static_cast<double>(report.state.counters.steps);
  const csim::SolverCounters& c = report.state.counters;
  std::printf("spheres  contacts  steps  ms/step median (min-max)    free  detect  assemble  solve  update (ms/step)"
              "  sparse  fallbacks  sweeps/solve  unconverged  max residual\n");
  std::printf("%7zu  %8zu  %5ld  %10.3f (%.3f-%.3f)  %6.3f  %6.3f  %8.3f  %5.3f  %6.3f  %6ld  %9ld  %12.1f  %11ld  %12.2e\n",
              spheres.size(), report.state.contacts.size(), c.steps, ms[ms.size() / 2], ms.front(), ms.back(),
              per * t.free_velocity, per * t.detection, per * t.assembly, per * t.solve, per * t.update, c.sparse_solves,
              c.dense_fallbacks, c.solves > 0 ? static_cast<double>(c.total_iterations) / c.solves : 0.0, c.not_converged,
              c.max_residual);
  if (sleep_speed != "0") std::printf("bodies asleep at the end: %d\n", report.state.counters.bodies_asleep);
  return 0;
}
