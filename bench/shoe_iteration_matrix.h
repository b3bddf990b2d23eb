// The FE shoe's matrices as the factor benchmarks take them: SDNV104's QUAD4 shoe at `divisions`
// (scenes/sdnv104-quad4), its stiffness K and mass M, and the iteration matrix A = M + h²θ²K with the
// Moreau–Jean step's h = 1e-3 s and θ = 0.51.
#pragma once

#include "engine/dynamics.h"
#include "tools/scene/scene.h"

#include <string>

struct ShoeMatrices {
  csim::SparseMatrix K, M;  // compressed
  csim::SparseMatrix iteration() const {
    const double h = 1e-3, theta = 0.51;
    return M + (h * h * theta * theta) * K;
  }
};

inline ShoeMatrices shoe_matrices(int divisions) {
  const auto scene = csim::load_scene(CSIM_SOURCE_DIR "/scenes/sdnv104-quad4/scene.yaml",
                                      {"parameters.divisions=" + std::to_string(divisions)});
  const csim::Dynamics dynamics(scene->world);
  ShoeMatrices shoe{dynamics.body_stiffness(), dynamics.mass()};
  shoe.K.makeCompressed();
  shoe.M.makeCompressed();
  return shoe;
}

inline csim::SparseMatrix shoe_iteration_matrix(int divisions) { return shoe_matrices(divisions).iteration(); }
