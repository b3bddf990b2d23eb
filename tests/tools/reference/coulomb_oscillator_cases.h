// The lumped models of the two friction benchmarks as Coulomb oscillators (tools/reference/
// coulomb_oscillator.h), shared by the reference's own tests and by the steppers' tests that run the
// benchmarks' scenes against it.
#pragma once

#include "tools/reference/coulomb_oscillator.h"

namespace csim::test {

// SDNV104 lumped: m = 7000 kg, k = 2 × 12 kN/m, push 200 kN, pressure 70 kN, μ = 0.3; the loads ramped
// over ramp_time (s; 0: applied at once).
inline CoulombOscillator sdnv104(double ramp_time) {
  return {.mass = 7000, .stiffness = 24000, .force = 200000, .normal_force = 70000, .mu = 0.3, .ramp_time = ramp_time};
}

// SDND100: m = 1 kg, k = 1e4 N/m, N = m g = 10 N, released from x0 = 0.85 mm; mu_effective the
// coefficient along the line of travel.
inline CoulombOscillator sdnd100(double mu_effective) {
  return {.mass = 1, .stiffness = 1e4, .normal_force = 10, .mu = mu_effective, .x0 = 0.85e-3};
}

}  // namespace csim::test
