// A settled pile of rigid spheres: the cost of a Moreau–Jean step with a few hundred frictional contacts
// between many bodies (run by hand: build/bench/bench_pile [spheres] [steps] [repeats]).
//
// The pile is settled by construction, so that no settling run precedes the measurement: layer k is a
// (a − k) × (b − k) square grid of spheres of radius R at a spacing s = 2.02 R (neighbours in a layer do
// not touch), each sphere of layer k + 1 resting in the hollow of four of layer k (its centre (s/2, s/2)
// across and sqrt(4R² − s²/2) above theirs), layer 0 on a rigid floor; a 9 × 8 base gives 72 + 56 + 42 +
// 30 = 200 spheres in four layers; other counts fill the layers in order (the last one partly). Every
// sphere touches the floor or four spheres below it, so a step's problem holds the 72 floor contacts and
// four per upper sphere (584 for 200 spheres) where a random settled pile has about two per body:
// W has a few nonzero 3 × 3 blocks per row, the sparsity of a physics-engine scene.
//
// Contacts are declared per pair of neighbours (each sphere with the floor, with its four supports and
// with its grid neighbours, which stay open), μ = 0.5, gravity 9.81, h = 1e-3, θ = ½, the contact
// solver's tolerance 1e-8. Printed: the spheres, the contacts of the last step, and ms per step, median
// and min–max over the repeats, with the stepper's phase timers of the last repeat.
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

namespace {

struct Sphere {
  double x, y, z;
  int layer, i, j;
};

// The pile's spheres, layer by layer, at most `count`.
std::vector<Sphere> pile(int count, int base_a, int base_b, double radius) {
  const double spacing = 2.02 * radius;
  const double rise = std::sqrt(4.0 * radius * radius - 0.5 * spacing * spacing);
  std::vector<Sphere> spheres;
  for (int layer = 0; static_cast<int>(spheres.size()) < count; ++layer) {
    const int a = base_a - layer, b = base_b - layer;
    if (a < 1 || b < 1) break;
    for (int i = 0; i < a && static_cast<int>(spheres.size()) < count; ++i)
      for (int j = 0; j < b && static_cast<int>(spheres.size()) < count; ++j)
        spheres.push_back({(i + 0.5 * layer) * spacing, (j + 0.5 * layer) * spacing, radius + layer * rise, layer, i, j});
  }
  return spheres;
}

std::string scene_text(const std::vector<Sphere>& spheres, double radius, int steps) {
  std::string text = "dimension: 3\ngravity: [0, 0, -9.81]\nbodies:\n";
  char line[512];
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    std::snprintf(line, sizeof line,
                  "  s%zu: {type: rigid, mass: 1, position: [%.17g, %.17g, %.17g], "
                  "shapes: {ball: {type: sphere, radius: %.17g}}}\n",
                  k, spheres[k].x, spheres[k].y, spheres[k].z, radius);
    text += line;
  }
  text += "  floor: {type: fixed, shapes: {surface: {type: halfspace, normal: [0, 0, 1], offset: 0}}}\n";
  text += "contacts:\n";
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    std::snprintf(line, sizeof line, "  f%zu: {between: [s%zu, floor], mu: 0.5}\n", k, k);
    text += line;
    for (std::size_t l = k + 1; l < spheres.size(); ++l) {
      const Sphere &p = spheres[k], &q = spheres[l];
      const bool same = p.layer == q.layer && std::abs(p.i - q.i) + std::abs(p.j - q.j) == 1;
      const bool on = q.layer == p.layer + 1 && (q.i == p.i || q.i == p.i - 1) && (q.j == p.j || q.j == p.j - 1);
      if (!same && !on) continue;
      std::snprintf(line, sizeof line, "  c%zu_%zu: {between: [s%zu, s%zu], mu: 0.5}\n", k, l, k, l);
      text += line;
    }
  }
  std::snprintf(line, sizeof line,
                "time: {end: %.17g, step: 1e-3}\nintegrator: {type: moreau-jean, theta: 0.5}\n"
                "contact_solver: {tolerance: 1e-8}\noutput: {rate: 1}\n",
                steps * 1e-3);
  text += line;
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  const int count = argc > 1 ? std::atoi(argv[1]) : 200;
  const int steps = argc > 2 ? std::atoi(argv[2]) : 5;
  const int repeats = argc > 3 ? std::atoi(argv[3]) : 3;
  const double radius = 0.1;
  const std::vector<Sphere> spheres = pile(count, 9, 8, radius);
  const std::string file = "/tmp/bench_pile_" + std::to_string(getpid()) + ".yaml";
  std::ofstream(file) << scene_text(spheres, radius, steps);
  const std::unique_ptr<csim::Scene> scene = csim::load_scene(file, {});
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
  std::printf("spheres  contacts  steps  ms/step median (min-max)    free  detect  assemble  solve  update (ms/step)\n");
  std::printf("%7zu  %8zu  %5ld  %10.3f (%.3f-%.3f)  %6.3f  %6.3f  %8.3f  %5.3f  %6.3f\n", spheres.size(),
              report.state.contacts.size(), report.state.counters.steps, ms[ms.size() / 2], ms.front(), ms.back(),
              per * t.free_velocity, per * t.detection, per * t.assembly, per * t.solve, per * t.update);
  return 0;
}
