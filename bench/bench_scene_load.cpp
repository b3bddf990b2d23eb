// Loading a scene of many bodies (run by hand: build/bench/bench_scene_load [repeats] [counts...]): the
// time to read a pile of N rigid spheres (bench/pile_scene.h, a 20 × 20 base filled layer by layer) with
// one group law between every two spheres and one between the floor and the group, and the time to
// construct its stepper (the contact detector's collision objects and law table; what `csim validate`
// does besides printing). Printed per N: the laws, the file's size, load_scene and make_stepper in ms
// (median and min–max over the repeats); the time per body should not grow with N.
// The same pile declared pair by pair (its neighbour pairs: about 5 laws a sphere) for comparison.
#include "bench/spread.h"
#include "bench/pile_scene.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

using csim::bench::Spread;
using csim::bench::spread;

double milliseconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 5;
  std::vector<int> counts;
  for (int k = 2; k < argc; ++k) counts.push_back(std::atoi(argv[k]));
  if (counts.empty()) counts = {250, 500, 1000, 2000};
  const double radius = 0.1;
  const int base = 20;
  std::printf("%-15s %6s %7s %9s  %-22s %-22s %s\n", "declaration", "bodies", "laws", "file (kB)",
              "load_scene ms (min-max)", "make_stepper ms", "load µs/body");
  for (const csim::bench::Declaration declaration :
       {csim::bench::Declaration::group, csim::bench::Declaration::neighbour_pairs}) {
    for (int count : counts) {
      const std::vector<csim::bench::Sphere> spheres = csim::bench::pile(count, base, base, radius);
      const std::string text = csim::bench::scene_text(spheres, radius, 1, base, base, 0.5, 20000, declaration);
      const std::string file = "/tmp/bench_scene_load_" + std::to_string(getpid()) + ".yaml";
      std::ofstream(file) << text;
      std::vector<double> load, stepper;
      std::size_t laws = 0;
      for (int r = 0; r < repeats; ++r) {
        auto start = std::chrono::steady_clock::now();
        const std::unique_ptr<csim::Scene> scene = csim::load_scene(file, {});
        load.push_back(milliseconds_since(start));
        laws = scene->world.contact_laws.size();
        start = std::chrono::steady_clock::now();
        const auto made = csim::make_stepper(scene->world, scene->run);
        stepper.push_back(milliseconds_since(start));
      }
      std::remove(file.c_str());
      const Spread l = spread(load), s = spread(stepper);
      char load_text[64], stepper_text[64];
      std::snprintf(load_text, sizeof load_text, "%.1f (%.1f-%.1f)", l.median, l.min, l.max);
      std::snprintf(stepper_text, sizeof stepper_text, "%.1f (%.1f-%.1f)", s.median, s.min, s.max);
      std::printf("%-15s %6zu %7zu %9.0f  %-22s %-22s %.0f\n",
                  declaration == csim::bench::Declaration::group ? "group" : "neighbour pairs", spheres.size() + 1,
                  laws, text.size() / 1e3, load_text, stepper_text, 1e3 * l.median / (spheres.size() + 1));
    }
  }
  return 0;
}
