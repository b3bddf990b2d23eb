// Speed and scale of finite-element contact (run by hand: build/bench/bench_fe [steps] [max divisions]).
// SDNV104 with an elastic QUAD4 shoe, divisions 5 … 160 (up to about 52 000 DOFs), a fixed number of
// steps from rest: DOFs, active contacts, factorization time, time per step by phase, peak memory.
// "steady" is the cost of a step once W is factored and the contacts' Delassus columns are cached:
// the difference between runs of 2N and N steps, divided by N (the one-time work cancels); "total"
// is the plain wall time per step of the N-step run, which includes it. The phase columns are
// sampled on one step in 16 and include the first step's one-time work: indicative only.
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>

namespace {

double peak_memory_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // kB on Linux
}

}  // namespace

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::atoi(argv[1]) : 200;
  const int largest = argc > 2 ? std::atoi(argv[2]) : 160;
  const std::string scene_file = CSIM_SOURCE_DIR "/scenes/sdnv104-quad4/scene.yaml";
  std::printf("SDNV104 elastic shoe (QUAD4), %d steps of 1e-3 s from rest; times per step in ms\n", steps);
  std::printf("%6s %8s %8s %10s %10s %10s %10s %10s %10s %10s %10s %9s\n", "div", "dofs", "contacts",
              "factor (s)", "total", "steady", "free v", "detect", "assemble", "solve", "update", "peak MB");
  double previous_dofs = 0, previous_time = 0;
  for (int divisions = 5; divisions <= largest; divisions *= 2) {
    // The scene's checks need the whole run and fail on this short one: only the cost matters here.
    const auto run = [&](int count) {
      const std::string end = std::to_string(count * 1e-3);
      // The literature checks' times must lie in the shortened window.
      const auto scene = csim::load_scene(
          scene_file, {"parameters.divisions=" + std::to_string(divisions), "time.end=" + end,
                       "checks.seed_x_170.at=" + end, "checks.seed_x_340.at=" + end});
      csim::RunReport report = csim::run_scene(*scene, {});
      return std::make_pair(scene->world.velocity_size, std::move(report));
    };
    const auto [dofs, report] = run(steps);
    const double doubled_wall = run(2 * steps).second.wall_time;
    const auto& s = report.state;
    const double n = s.counters.steps;
    const auto& t = s.timers;
    const double per_step = report.wall_time / n * 1e3;
    const double steady = (doubled_wall - report.wall_time) / n * 1e3;
    std::printf("%6d %8d %8.1f %10.4f %10.3f %10.3f %10.3f %10.3f %10.3f %10.3f %10.3f %9.0f", divisions, dofs,
                s.counters.contact_points / n, s.factorization_seconds, per_step, steady,
                t.free_velocity / n * 1e3, t.detection / n * 1e3, t.assembly / n * 1e3, t.solve / n * 1e3,
                t.update / n * 1e3, peak_memory_mb());
    if (previous_dofs > 0)
      std::printf("   slope %.2f", std::log(steady / previous_time) / std::log(dofs / previous_dofs));
    std::printf("\n");
    previous_dofs = dofs;
    previous_time = steady;
  }
  return 0;
}
