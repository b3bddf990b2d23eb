// Cost of the finite-strain element kernels (run by hand: build/bench/bench_finite_strain [repeats]).
// The rolling ring's meshes (68 × 10 annulus, r_i 1, R 2; hexa8 one element wide) at a fixed
// deformed state (a smooth displacement of 5 % of the radius), every law and formulation the scenes
// use: the time of one assembly of force and tangent (assemble_finite_strain) per element, the
// median of the repeats, and of force alone (internal_force) for comparison.
#include "fem/finite_strain.h"
#include "fem/mesh_generators.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

using csim::ElementType;
using csim::FiniteStrainFormulation;

template <class Work>
double median_seconds(int repeats, Work&& work) {
  std::vector<double> times;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    work();
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::nth_element(times.begin(), times.begin() + repeats / 2, times.end());
  return times[repeats / 2];
}

struct Case {
  const char* name;
  csim::Mesh mesh;
  csim::HyperelasticMaterial material;
  FiniteStrainFormulation formulation;
};

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 21;
  const csim::HyperelasticMaterial mooney = csim::mooney_rivlin(80, 20, 200000, 1);
  const csim::HyperelasticMaterial neo = csim::neo_hookean(800, 0.3, 1);
  const std::vector<Case> cases = {
      {"quad4 Mooney-Rivlin, mean dilatation", csim::annulus_mesh(1, 2, 68, 10, ElementType::quad4), mooney,
       FiniteStrainFormulation::mean_dilatation},
      {"quad4 neo-Hookean, mean dilatation", csim::annulus_mesh(1, 2, 68, 10, ElementType::quad4), neo,
       FiniteStrainFormulation::mean_dilatation},
      {"quad8 Mooney-Rivlin, linear dilatation", csim::annulus_mesh(1, 2, 36, 6, ElementType::quad8), mooney,
       FiniteStrainFormulation::linear_dilatation},
      {"quad8 neo-Hookean, standard", csim::annulus_mesh(1, 2, 36, 6, ElementType::quad8), neo,
       FiniteStrainFormulation::standard},
      {"hexa8 Mooney-Rivlin, mean dilatation", csim::annulus_mesh_3d(1, 2, 0.2, 68, 10, 1), mooney,
       FiniteStrainFormulation::mean_dilatation},
      {"hexa8 neo-Hookean, mean dilatation", csim::annulus_mesh_3d(1, 2, 0.2, 68, 10, 1), neo,
       FiniteStrainFormulation::mean_dilatation},
  };
  std::printf("Finite-strain kernels, median of %d assemblies; microseconds per element\n", repeats);
  std::printf("%-40s %9s %16s %12s\n", "mesh and law", "elements", "force+tangent", "force only");
  for (const Case& c : cases) {
    const csim::FiniteStrainModel model{c.mesh, c.material, 1.0, c.formulation};
    const int d = c.mesh.dimension();
    Eigen::VectorXd u(d * static_cast<Eigen::Index>(c.mesh.nodes.size()));
    for (std::size_t a = 0; a < c.mesh.nodes.size(); ++a) {
      const Eigen::Vector3d& X = c.mesh.nodes[a];
      const double angle = std::atan2(X.y(), X.x());
      u(d * a) = 0.1 * std::sin(2 * angle) * X.norm() / 2;
      u(d * a + 1) = -0.1 * std::cos(angle) * X.norm() / 2;
      if (d == 3) u(d * a + 2) = 0.0;
    }
    Eigen::VectorXd force;
    std::vector<Eigen::Triplet<double>> triplets;
    const double elements = static_cast<double>(c.mesh.elements.size());
    const double full = median_seconds(repeats, [&] { csim::assemble_finite_strain(model, u, force, triplets); });
    const double alone = median_seconds(repeats, [&] { csim::internal_force(model, u, force); });
    std::printf("%-40s %9.0f %16.2f %12.2f\n", c.name, elements, full / elements * 1e6, alone / elements * 1e6);
  }
}
