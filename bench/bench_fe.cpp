// Speed and scale of finite-element contact (run by hand:
//   OMP_NUM_THREADS=1 build/bench/bench_fe [short steps] [long steps] [repeats] [max divisions]).
// SDNV104 with an elastic QUAD4 shoe, divisions 5 … 160 (up to about 52 000 DOFs), runs from rest:
// DOFs, active contacts, time per step, peak memory. "steady" is the cost of a step once A is
// factored and the contacts' Delassus entries are kept: the difference between the wall times of a
// long and a short run, divided by the difference of their steps (the one-time work cancels), the
// median of `repeats` pairs with its spread min–max beside it; the slope is log(steady) against
// log(DOFs) from the previous size. "one-time" is the short run's time less its steps at the steady
// cost: the factorization, the first contacts' Delassus entries and the set-up (median). The phase
// columns are sampled on one step in 16 of the last long run and include the first step's one-time
// work: indicative only.
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

namespace {

double peak_memory_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // kB on Linux
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  const int short_steps = argc > 1 ? std::atoi(argv[1]) : 200;
  const int long_steps = argc > 2 ? std::atoi(argv[2]) : 1200;
  const int repeats = argc > 3 ? std::atoi(argv[3]) : 5;
  const int largest = argc > 4 ? std::atoi(argv[4]) : 160;
  const std::string scene_file = CSIM_SOURCE_DIR "/scenes/sdnv104-quad4/scene.yaml";
  std::printf("SDNV104 elastic shoe (QUAD4) from rest, steps of 1e-3 s; steady = (long − short run) / %d steps, "
              "median of %d [min–max]; times per step in ms\n",
              long_steps - short_steps, repeats);
  std::printf("%5s %7s %8s %10s %22s %6s %12s %8s %8s %8s %8s %8s %8s\n", "div", "dofs", "contacts", "factor (s)",
              "steady [min-max]", "slope", "one-time (s)", "free v", "detect", "assemble", "solve", "update",
              "peak MB");
  double previous_dofs = 0, previous_time = 0;
  for (int divisions = 5; divisions <= largest; divisions *= 2) {
    // The scene's checks need the whole run and fail on a short one: only the cost matters here.
    const auto run = [&](int count) {
      const std::string end = std::to_string(count * 1e-3);
      // The literature checks' times must lie in the shortened window.
      const auto scene = csim::load_scene(
          scene_file, {"parameters.divisions=" + std::to_string(divisions), "time.end=" + end,
                       "checks.seed_x_170.at=" + end, "checks.seed_x_340.at=" + end});
      csim::RunReport report = csim::run_scene(*scene, {});
      return std::make_pair(scene->world.velocity_size, std::move(report));
    };
    std::vector<double> steady, one_time;
    int dofs = 0;
    csim::RunReport last;
    for (int r = 0; r < repeats; ++r) {
      auto [size, brief] = run(short_steps);
      auto [unused, full] = run(long_steps);
      dofs = size;
      const double per_step = (full.wall_time - brief.wall_time) / (long_steps - short_steps);
      steady.push_back(per_step * 1e3);
      one_time.push_back(brief.wall_time - short_steps * per_step);
      last = std::move(full);
    }
    const auto& s = last.state;
    const double n = s.counters.steps;
    const auto& t = s.timers;
    const double middle = median(steady);
    std::printf("%5d %7d %8.1f %10.4f %8.3f [%5.3f-%5.3f] %6s %12.3f %8.3f %8.3f %8.3f %8.3f %8.3f %8.0f\n",
                divisions, dofs, s.counters.contact_points / n, s.factorization_seconds, middle,
                *std::min_element(steady.begin(), steady.end()), *std::max_element(steady.begin(), steady.end()),
                previous_dofs > 0 ? std::to_string(std::log(middle / previous_time) / std::log(dofs / previous_dofs))
                                        .substr(0, 5)
                                        .c_str()
                                  : "",
                median(one_time), t.free_velocity / n * 1e3, t.detection / n * 1e3, t.assembly / n * 1e3,
                t.solve / n * 1e3, t.update / n * 1e3, peak_memory_mb());
    std::fflush(stdout);
    previous_dofs = dofs;
    previous_time = middle;
  }
  return 0;
}
