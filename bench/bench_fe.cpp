// Speed and scale of finite-element contact (run by hand:
//   OMP_NUM_THREADS=1 build/bench/bench_fe [short steps] [long steps] [repeats] [max divisions]).
// SDNV104 with an elastic QUAD4 shoe, divisions 5 … 160 (up to about 52 000 DOFs), runs from rest:
// DOFs, active contacts, time per step, peak memory. "steady" is the cost of a step once A is
// factored and the contacts' Delassus entries are kept: the difference between the wall times of a
// long and a short run, divided by the difference of their steps (the one-time work cancels), the
// median of `repeats` pairs with its spread min–max beside it. Each repeat runs every size in turn,
// smallest first, so that a size and the next are measured minutes apart at most, under the same load
// of a shared host; the slope is log(steady) against log(DOFs) from the previous size within each
// repeat, its median and spread over the repeats. "one-time" is the short run's time less its steps
// at the steady cost: the factorization, the first contacts' Delassus entries and the set-up (median).
// The phase columns are sampled on one step in 16 of the last long run and include the first step's
// one-time work: indicative only. Peak memory is the process's after a size's first repeat: the sizes
// of that repeat grow, so it is that size's.
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
              "median of %d [min–max], the sizes in turn within each repeat; times per step in ms\n",
              long_steps - short_steps, repeats);
  struct Size {
    int divisions = 0, dofs = 0;
    std::vector<double> steady, one_time;
    csim::RunReport last;
    double peak_mb = 0;
  };
  std::vector<Size> sizes;
  for (int divisions = 5; divisions <= largest; divisions *= 2) {
    sizes.emplace_back();
    sizes.back().divisions = divisions;
  }
  for (int r = 0; r < repeats; ++r) {
    for (Size& size : sizes) {
      // The scene's checks need the whole run and fail on a short one: only the cost matters here.
      const auto run = [&](int count) {
        const std::string end = std::to_string(count * 1e-3);
        // The literature checks' times must lie in the shortened window.
        const auto scene = csim::load_scene(
            scene_file, {"parameters.divisions=" + std::to_string(size.divisions), "time.end=" + end,
                         "checks.seed_x_170.at=" + end, "checks.seed_x_340.at=" + end});
        csim::RunReport report = csim::run_scene(*scene, {});
        return std::make_pair(scene->world.velocity_size, std::move(report));
      };
      auto [dofs, brief] = run(short_steps);
      auto [unused, full] = run(long_steps);
      size.dofs = dofs;
      const double per_step = (full.wall_time - brief.wall_time) / (long_steps - short_steps);
      size.steady.push_back(per_step * 1e3);
      size.one_time.push_back(brief.wall_time - short_steps * per_step);
      size.last = std::move(full);
      if (r == 0) size.peak_mb = peak_memory_mb();
    }
  }
  std::printf("%5s %7s %8s %10s %22s %20s %12s %8s %8s %8s %8s %8s %8s\n", "div", "dofs", "contacts", "factor (s)",
              "steady [min-max]", "slope [min-max]", "one-time (s)", "free v", "detect", "assemble", "solve", "update",
              "peak MB");
  for (std::size_t k = 0; k < sizes.size(); ++k) {
    const Size& size = sizes[k];
    std::string slope;
    if (k > 0) {
      std::vector<double> slopes;
      for (int r = 0; r < repeats; ++r)
        slopes.push_back(std::log(size.steady[r] / sizes[k - 1].steady[r]) /
                         std::log(double(size.dofs) / sizes[k - 1].dofs));
      char text[64];
      std::snprintf(text, sizeof text, "%.3f [%.3f-%.3f]", median(slopes),
                    *std::min_element(slopes.begin(), slopes.end()), *std::max_element(slopes.begin(), slopes.end()));
      slope = text;
    }
    const auto& s = size.last.state;
    const double n = s.counters.steps;
    const auto& t = s.timers;
    std::printf("%5d %7d %8.1f %10.4f %8.3f [%5.3f-%5.3f] %20s %12.3f %8.3f %8.3f %8.3f %8.3f %8.3f %8.0f\n",
                size.divisions, size.dofs, s.counters.contact_points / n, s.factorization_seconds, median(size.steady),
                *std::min_element(size.steady.begin(), size.steady.end()),
                *std::max_element(size.steady.begin(), size.steady.end()), slope.c_str(), median(size.one_time),
                t.free_velocity / n * 1e3, t.detection / n * 1e3, t.assembly / n * 1e3, t.solve / n * 1e3,
                t.update / n * 1e3, size.peak_mb);
  }
  return 0;
}
