// A pile of rigid spheres packed in a box, settled by construction (bench_pile.cpp, and the sparse
// contact stage's test): layer k is a (a − k) × (b − k) square grid of spheres of radius R at a spacing 2R
// (neighbours in a layer touch), each sphere of layer k + 1 resting in the hollow of four of layer k (its
// centre (R, R) across and √2 R above theirs), layer 0 on the floor and against the box's four walls,
// which take the layers' outward thrust: a statically admissible packing, frictionless or not.
// Contacts are declared per pair of neighbours (each sphere with the floor and walls, with the spheres
// beside it and with its four supports), or by group: every sphere in the group `spheres`, one law
// between every two of them and one between the floor and the group (docs/contract.md, contacts).
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace csim::bench {

enum class Declaration { neighbour_pairs, group };

struct Sphere {
  double x, y, z;
  int layer, i, j;
};

// The pile's spheres, layer by layer, at most `count`.
inline std::vector<Sphere> pile(int count, int base_a, int base_b, double radius) {
  const double spacing = 2.0 * radius;
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

// The scene file of these spheres in a box of base_a × base_b (the base layer's extent), `steps` steps of
// 1 ms, Coulomb μ on every contact, the contact solver's tolerance 1e-8 and at most max_iterations sweeps.
inline std::string scene_text(const std::vector<Sphere>& spheres, double radius, int steps, int base_a, int base_b,
                              double mu = 0.5, int max_iterations = 20000,
                              Declaration declaration = Declaration::neighbour_pairs) {
  const bool by_group = declaration == Declaration::group;
  std::string text = "dimension: 3\ngravity: [0, 0, -9.81]\nbodies:\n";
  char line[512];
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    std::snprintf(line, sizeof line,
                  "  s%zu: {type: rigid, mass: 1, position: [%.17g, %.17g, %.17g], "
                  "shapes: {ball: {type: sphere, radius: %.17g}}%s}\n",
                  k, spheres[k].x, spheres[k].y, spheres[k].z, radius, by_group ? ", group: spheres" : "");
    text += line;
  }
  // The floor and the box's four walls, touching the base layer's outer spheres.
  const double x_max = (base_a - 1) * 2.0 * radius + radius, y_max = (base_b - 1) * 2.0 * radius + radius;
  std::snprintf(line, sizeof line,
                "  floor: {type: fixed, shapes: {surface: {type: halfspace, normal: [0, 0, 1], offset: 0},\n"
                "    west: {type: halfspace, normal: [1, 0, 0], offset: %.17g},\n"
                "    east: {type: halfspace, normal: [-1, 0, 0], offset: %.17g},\n"
                "    south: {type: halfspace, normal: [0, 1, 0], offset: %.17g},\n"
                "    north: {type: halfspace, normal: [0, -1, 0], offset: %.17g}}}\n",
                -radius, -x_max, -radius, -y_max);
  text += line;
  text += "contacts:\n";
  if (by_group) {
    std::snprintf(line, sizeof line, "  floor: {between: [floor, spheres], mu: %.17g}\n"
                  "  pile: {between: [spheres, spheres], mu: %.17g}\n", mu, mu);
    text += line;
  }
  for (std::size_t k = 0; k < spheres.size() && !by_group; ++k) {
    std::snprintf(line, sizeof line, "  f%zu: {between: [s%zu, floor], mu: %.17g}\n", k, k, mu);
    text += line;
    for (std::size_t l = k + 1; l < spheres.size(); ++l) {
      const Sphere &p = spheres[k], &q = spheres[l];
      const bool same = p.layer == q.layer && std::abs(p.i - q.i) + std::abs(p.j - q.j) == 1;
      const bool on = q.layer == p.layer + 1 && (q.i == p.i || q.i == p.i - 1) && (q.j == p.j || q.j == p.j - 1);
      if (!same && !on) continue;
      std::snprintf(line, sizeof line, "  c%zu_%zu: {between: [s%zu, s%zu], mu: %.17g}\n", k, l, k, l, mu);
      text += line;
    }
  }
  std::snprintf(line, sizeof line,
                "time: {end: %.17g, step: 1e-3}\nintegrator: {type: moreau-jean, theta: 0.5}\n"
                "contact_solver: {tolerance: 1e-8, max_iterations: %d}\noutput: {rate: 1}\n",
                steps * 1e-3, max_iterations);
  text += line;
  return text;
}

// The same scene text under the generalized-α stepper, the spheres point masses (that stepper integrates
// no rotation of a rigid body in space; the packing is statically admissible without them).
inline std::string generalized_alpha_text(std::string text) {
  for (std::size_t at = text.find("type: rigid"); at != std::string::npos; at = text.find("type: rigid", at))
    text.replace(at, 11, "type: point");
  const std::string moreau_jean = "integrator: {type: moreau-jean, theta: 0.5}";
  text.replace(text.find(moreau_jean), moreau_jean.size(), "integrator: {type: generalized-alpha}");
  return text;
}

}  // namespace csim::bench

