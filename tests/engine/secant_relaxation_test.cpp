// Newton's step length from the secant model (engine/steppers/secant_relaxation.h), on the iteration
// it is meant for: a model whose stiffness along one mode is the true one over c, so that each step
// Δx = c (x* − x) leaves the fraction 1 − c of the error (c < 1: creeping; c > 1: overshooting).
#include "engine/steppers/secant_relaxation.h"

#include <gtest/gtest.h>

#include <cmath>

namespace csim {
namespace {

// Iterations of x ← x + ω Δx from x = 0 to |x* − x| ≤ 1e-12 (x* = (1, 2)), at most `limit`.
int iterations_to_converge(double c, bool relaxed, int limit = 1000) {
  const Vector target = (Vector(2) << 1.0, 2.0).finished();
  Vector x = Vector::Zero(2);
  SecantRelaxation relaxation;
  relaxation.reset();
  for (int j = 1; j <= limit; ++j) {
    const Vector step = c * (target - x);
    if (step.lpNorm<Eigen::Infinity>() <= 1e-12) return j;
    x += (relaxed ? relaxation.next(step) : 1.0) * step;
  }
  return limit + 1;
}

TEST(SecantRelaxation, ExtrapolatesASteadyLinearRateToItsFixedPoint) {
  // ρ = 0.9: 248 plain iterations to 1e-12; extrapolated once ρ has been seen steady (third step),
  // the step 1/(1 − ρ) lands on x*.
  EXPECT_GT(iterations_to_converge(0.1, false), 200);
  EXPECT_LE(iterations_to_converge(0.1, true), 5);
}

TEST(SecantRelaxation, DampsAnOscillation) {
  // ρ = −1.44 (the quasi-static elastic ring of the header): plain iterations diverge; the secant
  // step ω/(1 − ρ) lands on x*.
  EXPECT_GT(iterations_to_converge(2.44, false), 1000);
  EXPECT_LE(iterations_to_converge(2.44, true), 4);
}

TEST(SecantRelaxation, LeavesNewtonAloneWhereItConverges) {
  SecantRelaxation relaxation;
  relaxation.reset();
  Vector step = (Vector(2) << 1.0, -1.0).finished();
  for (int j = 0; j < 5; ++j) {  // quadratic convergence: the ratio falls, never steady in (½, 1)
    EXPECT_EQ(relaxation.next(step), 1.0) << j;
    step *= 0.1 / (j + 1);
  }
  // A steady rate of 0.9 along steps that turn (cosine < 0.9): not one mode, not extrapolated.
  relaxation.reset();
  for (int j = 0; j < 4; ++j) {
    const double angle = 0.6 * j;
    step = std::pow(0.9, j) * (Vector(2) << std::cos(angle), std::sin(angle)).finished();
    EXPECT_EQ(relaxation.next(step), 1.0) << j;
  }
}

}  // namespace
}  // namespace csim
