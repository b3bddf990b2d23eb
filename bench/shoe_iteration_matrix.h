// The FE shoe's iteration matrix as the factor benchmarks take it: SDNV104's QUAD4 shoe at `divisions`
// (scenes/sdnv104-quad4), A = M + h²θ²K with the Moreau–Jean step's h = 1e-3 s and θ = 0.51.
#pragma once

#include "engine/dynamics.h"
#include "tools/scene/scene.h"

#include <string>

inline csim::SparseMatrix shoe_iteration_matrix(int divisions) {
  const auto scene = csim::load_scene(CSIM_SOURCE_DIR "/scenes/sdnv104-quad4/scene.yaml",
                                      {"parameters.divisions=" + std::to_string(divisions)});
  const csim::Dynamics dynamics(scene->world);
  const double h = 1e-3, theta = 0.51;
  return dynamics.mass() + (h * h * theta * theta) * dynamics.body_stiffness();
}
