// The parameters of the nonsmooth generalized-α stepper (generalized_alpha.h), apart from the stepper
// so that the scene settings can hold them without the stepper's dependencies.
#pragma once

#include "contact/pgs_solver.h"
#include "engine/contact_stage/iteration_operator.h"

namespace csim {

// What only the generalized-α stepper reads (the scene key integrator.rho_infinity).
struct GeneralizedAlphaOptions {
  // ρ∞ ∈ [0, 1]: the spectral radius of the scheme at ωh → ∞. 1 keeps every mode (the trapezoidal
  // rule: Newmark's average acceleration); smaller values damp the modes the step does not resolve,
  // and leave the resolved ones to O((ωh)³) a step.
  double rho_infinity = 0.8;
};

struct GeneralizedAlphaParameters : GeneralizedAlphaOptions {
  double step = 1e-3;              // h, s
  PgsParameters solver;
  double failure_residual = 1e-6;  // a solve left above this relative residual stops the run
  DelassusChoice delassus_storage = DelassusChoice::automatic;  // contact_solver.storage
};

// The coefficients of Chung & Hulbert (J. Appl. Mech. 1993) for a spectral radius ρ∞: second order,
// unconditionally stable on linear systems, the high frequencies damped to ρ∞.
struct GeneralizedAlphaCoefficients {
  explicit GeneralizedAlphaCoefficients(double rho_infinity)
      : alpha_m((2.0 * rho_infinity - 1.0) / (rho_infinity + 1.0)),
        alpha_f(rho_infinity / (rho_infinity + 1.0)),
        gamma(0.5 - alpha_m + alpha_f),
        beta(0.25 * (gamma + 0.5) * (gamma + 0.5)) {}
  double alpha_m, alpha_f, gamma, beta;
  // ẅ_{n+1}'s weight in a_{n+1}: (1 − α_f) / (1 − α_m).
  double acceleration_weight() const { return (1.0 - alpha_f) / (1.0 - alpha_m); }
};

}  // namespace csim
