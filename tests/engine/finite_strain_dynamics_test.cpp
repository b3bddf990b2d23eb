// Moreau–Jean with Newton iterations on a finite-strain body (scenes/spinning-bar): the step's
// energy error is second order in h at θ = ½, and Newton converges quadratically (the tangent is
// exact), so a step takes at most three iterations.
#include "engine/run.h"
#include "engine/scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>

namespace csim {
namespace {

const std::string kSpinningBar = CSIM_SOURCE_DIR "/scenes/spinning-bar/scene.yaml";

// The largest |E(t) − E(0)| over the samples (every 0.01 s; the error oscillates with the stretch).
double energy_error(const std::string& step, RunReport* out = nullptr) {
  const auto scene = load_scene(kSpinningBar, {"parameters.step=" + step});
  RunReport report = run_scene(*scene, {});
  const int mechanical = 2;  // probes: tip_x, tip_y, mechanical, elastic
  double error = 0.0;
  for (const auto& row : report.samples)
    error = std::max(error, std::abs(row[mechanical] - report.samples.front()[mechanical]));
  if (out) *out = std::move(report);
  return error;
}

TEST(FiniteStrainDynamics, EnergyErrorIsSecondOrderInTheStep) {
  const double coarse = energy_error("4e-3"), medium = energy_error("2e-3"), fine = energy_error("1e-3");
  ASSERT_GT(fine, 0.0);  // not exactly conservative: the trapezoidal rule on a nonlinear force
  EXPECT_GT(coarse / medium, 3.0) << coarse << " " << medium;
  EXPECT_GT(medium / fine, 3.0) << medium << " " << fine;
}

TEST(FiniteStrainDynamics, NewtonConvergesQuadratically) {
  RunReport report;
  energy_error("1e-3", &report);
  const SolverCounters& c = report.state.counters;
  EXPECT_GT(c.newton_iterations, 0);
  EXPECT_LE(c.max_newton_iterations, 3);
  EXPECT_EQ(c.newton_regularized, 0);  // a free bar's tangent plus mass is positive definite
  EXPECT_TRUE(report.all_passed());
}

}  // namespace
}  // namespace csim
