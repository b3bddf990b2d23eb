#include "tools/reference/coulomb_oscillator.h"

#include "tests/tools/reference/coulomb_oscillator_cases.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace csim {
namespace {

using test::sdnd100;
using test::sdnv104;

constexpr double pi = std::numbers::pi;

// |actual − expected| ≤ tolerance·|expected|
::testing::AssertionResult near_relative(double actual, double expected, double tolerance) {
  if (std::abs(actual - expected) <= tolerance * std::abs(expected)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "actual " << std::setprecision(17) << actual << " vs expected " << expected
                                       << ": relative difference " << std::abs(actual - expected) / std::abs(expected)
                                       << " > " << tolerance;
}

// ---------------------------------------------------------------------------------------------------
// An independent numerical reference: RK4 on the slip ODE with fixed step, events located by bisection
// on re-integrated sub-steps (velocity zero, stick release), the ramp end stepped onto exactly.

struct NumericalEvent {
  double time;
  double position;
};

struct NumericalSolution {
  std::vector<NumericalEvent> stops;  // every velocity zero that ends a slip
  bool at_rest = false;
  double rest_position = 0;
  std::vector<double> samples;  // m, the positions at the requested sample times
};

// sample_times: sorted, in [0, t_end]; the steps land on them exactly.
NumericalSolution integrate_rk4(const CoulombOscillator& m, double t_end, double dt,
                                const std::vector<double>& sample_times = {}) {
  const double friction = m.mu * m.normal_force;
  auto lambda = [&](double t) { return m.ramp_time > 0 && t < m.ramp_time ? t / m.ramp_time : 1.0; };
  auto accel = [&](double t, double x, double s) {
    return (lambda(t) * (m.force - s * friction) - m.stiffness * x) / m.mass;
  };
  struct State {
    double x, v;
  };
  auto rk4 = [&](double t, State y, double h, double s) {
    const double k1x = y.v, k1v = accel(t, y.x, s);
    const double k2x = y.v + 0.5 * h * k1v, k2v = accel(t + 0.5 * h, y.x + 0.5 * h * k1x, s);
    const double k3x = y.v + 0.5 * h * k2v, k3v = accel(t + 0.5 * h, y.x + 0.5 * h * k2x, s);
    const double k4x = y.v + h * k3v, k4v = accel(t + h, y.x + h * k3x, s);
    return State{y.x + h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x), y.v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)};
  };
  // > 0 when the stuck mass at x must slip.
  auto violation = [&](double t, double x) {
    return std::abs(lambda(t) * m.force - m.stiffness * x) - lambda(t) * friction;
  };
  auto bisect = [](double lo, double hi, auto is_past) {
    for (int i = 0; i < 80 && hi - lo > 0; ++i) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      (is_past(mid) ? hi : lo) = mid;
    }
    return hi;
  };

  NumericalSolution out;
  double t = 0;
  State y{m.x0, m.v0};
  double s = y.v > 0 ? 1 : (y.v < 0 ? -1 : 0);  // 0 = stick
  auto from_rest = [&] {
    const double unbalanced = lambda(t) * m.force - m.stiffness * y.x;
    s = violation(t, y.x) > 0 ? (unbalanced > 0 ? 1 : -1) : 0;
  };
  if (s == 0) from_rest();
  std::size_t next_sample = 0;
  for (;;) {
    while (next_sample < sample_times.size() && sample_times[next_sample] <= t) {
      out.samples.push_back(y.x);
      ++next_sample;
    }
    if (t >= t_end) break;
    double h = std::min(dt, t_end - t);
    if (t < m.ramp_time) h = std::min(h, m.ramp_time - t);
    if (next_sample < sample_times.size()) h = std::min(h, sample_times[next_sample] - t);
    if (s == 0) {
      if (t >= m.ramp_time) {
        out.at_rest = true;
        out.rest_position = y.x;
        out.samples.resize(sample_times.size(), y.x);
        return out;
      }
      if (violation(t + h, y.x) > 0) {
        t = bisect(t, t + h, [&](double tt) { return violation(tt, y.x) > 0; });
        s = lambda(t) * m.force - m.stiffness * y.x > 0 ? 1 : -1;
      } else {
        t += h;
      }
      continue;
    }
    const State next = rk4(t, y, h, s);
    if (s * next.v > 0) {
      t += h;
      y = next;
      continue;
    }
    const double u = bisect(0, h, [&](double hh) { return s * rk4(t, y, hh, s).v <= 0; });
    y = State{rk4(t, y, u, s).x, 0.0};
    t += u;
    out.stops.push_back({t, y.x});
    from_rest();
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------
// SDNV104

TEST(CoulombOscillator, Sdnv104StepLoadMatchesTheHalfCycleFormula) {
  const CoulombOscillator model = sdnv104(0.0);
  const CoulombOscillatorSolution solution(model, 10.0);
  const double f = model.mu * model.normal_force, F = model.force, k = model.stiffness;
  const double T = pi / std::sqrt(k / model.mass);
  EXPECT_NEAR(T, 1.696654, 1e-6);

  ASSERT_EQ(solution.extremum_count(), 5);
  const double printed[] = {14.916667, 3.5, 11.416667, 7.0, 7.916667};
  for (int n = 1; n <= 5; ++n) {
    const int p = (n + 1) / 2;
    const double formula = n % 2 == 1 ? 2 * (F - (2 * p - 1) * f) / k : 4 * p * f / k;
    EXPECT_TRUE(near_relative(solution.extremum_value(n), formula, 1e-12)) << "extremum " << n;
    EXPECT_NEAR(solution.extremum_value(n), printed[n - 1], 5e-7) << "extremum " << n;
    EXPECT_NEAR(solution.extremum_time(n), n * T, 1e-12) << "extremum " << n;
    EXPECT_NEAR(solution.position(n * T), formula, 1e-9);
  }
  ASSERT_TRUE(solution.comes_to_rest());
  EXPECT_NEAR(solution.rest_time(), 5 * T, 1e-12);
  EXPECT_TRUE(near_relative(solution.rest_position(), 2 * (F - 5 * f) / k, 1e-12));
  // The rest position lies in the band |F − kx| ≤ f, and the mass stays there.
  EXPECT_LE(std::abs(F - k * solution.rest_position()), f);
  EXPECT_EQ(solution.position(9.5), solution.rest_position());
  EXPECT_EQ(solution.velocity(9.5), 0.0);
  // Inside the first half cycle: harmonic about (F − f)/k.
  const double c = (F - f) / k, w = std::sqrt(k / model.mass);
  EXPECT_TRUE(near_relative(solution.position(0.6), c * (1 - std::cos(w * 0.6)), 1e-13));
  EXPECT_TRUE(near_relative(solution.velocity(0.6), c * w * std::sin(w * 0.6), 1e-13));
}

// With the load ramped over τ the first half cycle is the step response averaged over [0, τ]: amplitude
// factor sinc(ωτ/2) = sin(ωτ/2)/(ωτ/2) and lag τ/2 (SPEC §1.7). After the ramp the half-cycle recurrence
// of the step load applies again.
TEST(CoulombOscillator, Sdnv104RampedLoadClosedFormAndPrintedValues) {
  const double tau = 0.07;
  const CoulombOscillator model = sdnv104(tau);
  const CoulombOscillatorSolution solution(model, 10.0);
  const double f = model.mu * model.normal_force, F = model.force, k = model.stiffness;
  const double w = std::sqrt(k / model.mass), T = pi / w;
  const double sinc = std::sin(w * tau / 2) / (w * tau / 2);
  EXPECT_NEAR(sinc, 0.99930, 5e-6);

  ASSERT_EQ(solution.extremum_count(), 5);
  const double c_up = (F - f) / k, c_down = (F + f) / k;
  double expected = c_up * (1 + sinc);
  for (int n = 1; n <= 5; ++n) {
    EXPECT_TRUE(near_relative(solution.extremum_value(n), expected, 1e-12)) << "extremum " << n;
    EXPECT_NEAR(solution.extremum_time(n), tau / 2 + n * T, 1e-12) << "extremum " << n;
    expected = 2 * (n % 2 == 1 ? c_down : c_up) - expected;
  }
  // SPEC §1.7, to the printed precision. Its 3.429 s is the Moreau–Jean extremum at Δt = 1e-3 s
  // (sdnv104_check.py; Δt = 1e-4 s gives 3.428): the exact τ/2 + 2T = 3.42831 s, so one unit of the last
  // printed digit is allowed there.
  EXPECT_NEAR(solution.extremum_value(1), 14.911, 5e-4);
  EXPECT_NEAR(solution.extremum_time(1), 1.732, 5e-4);
  EXPECT_NEAR(solution.extremum_value(2), 3.505, 5e-4);
  EXPECT_NEAR(solution.extremum_time(2), 3.429, 1e-3);
  ASSERT_TRUE(solution.comes_to_rest());
  EXPECT_NEAR(solution.rest_position(), 7.911, 5e-4);
  EXPECT_EQ(solution.rest_time(), solution.extremum_time(5));
  EXPECT_EQ(solution.rest_position(), solution.extremum_value(5));

  // Continuity across the ramp end, where the closed form changes.
  EXPECT_NEAR(solution.position(tau * (1 - 1e-12)), solution.position(tau), 1e-12);
  EXPECT_NEAR(solution.velocity(tau * (1 - 1e-12)), solution.velocity(tau), 1e-9);
  // During the ramp: x = c·(t/τ − sin ωt/(ωτ)).
  const double t = 0.05;
  EXPECT_TRUE(near_relative(solution.position(t), c_up * (t / tau - std::sin(w * t) / (w * tau)), 1e-10));
}

TEST(CoulombOscillator, Sdnv104RampedLoadAgreesWithFineRk4) {
  const CoulombOscillator model = sdnv104(0.07);
  const CoulombOscillatorSolution solution(model, 9.0);
  const NumericalSolution numerical = integrate_rk4(model, 9.0, 1e-6);
  ASSERT_EQ(static_cast<int>(numerical.stops.size()), solution.extremum_count());
  for (int n = 1; n <= solution.extremum_count(); ++n) {
    EXPECT_TRUE(near_relative(solution.extremum_time(n), numerical.stops[n - 1].time, 1e-7)) << "extremum " << n;
    EXPECT_TRUE(near_relative(solution.extremum_value(n), numerical.stops[n - 1].position, 1e-7)) << "extremum " << n;
  }
  ASSERT_TRUE(numerical.at_rest);
  ASSERT_TRUE(solution.comes_to_rest());
  EXPECT_TRUE(near_relative(solution.rest_position(), numerical.rest_position, 1e-7));
}

// ---------------------------------------------------------------------------------------------------
// SDND100

void expect_sdnd100_recurrence(const CoulombOscillatorSolution& solution, double c) {
  double r = 0.85e-3;
  for (int n = 1; n <= solution.extremum_count(); ++n) {
    r = -(r - 2 * c * (r > 0 ? 1 : -1));
    EXPECT_TRUE(near_relative(solution.extremum_value(n), r, 1e-12)) << "extremum " << n;
    EXPECT_NEAR(solution.extremum_time(n), n * pi / 100, 1e-15) << "extremum " << n;
  }
  ASSERT_TRUE(solution.comes_to_rest());
  EXPECT_LE(std::abs(solution.rest_position()), c);
  EXPECT_GT(std::abs(solution.extremum_value(solution.extremum_count() - 1)), c);
}

TEST(CoulombOscillator, Sdnd100IsotropicFriction) {
  const CoulombOscillatorSolution solution(sdnd100(0.1), 0.3);
  const double printed[] = {-6.5e-4, 4.5e-4, -2.5e-4, 5e-5};
  for (int n = 1; n <= 4; ++n) EXPECT_TRUE(near_relative(solution.position(n * pi / 100), printed[n - 1], 1e-4));
  ASSERT_EQ(solution.extremum_count(), 4);  // stops at r(t5) = 5e-5 ≤ c = 1e-4
  expect_sdnd100_recurrence(solution, 1e-4);
  EXPECT_NEAR(solution.rest_time(), 4 * pi / 100, 1e-15);
  EXPECT_EQ(solution.position(0.2), solution.rest_position());
}

TEST(CoulombOscillator, Sdnd100UnidirectionalFriction) {
  const double mu_effective = 0.1 * std::cos(pi / 4);
  const CoulombOscillatorSolution solution(sdnd100(mu_effective), 0.3);
  const double printed[] = {-7.0858e-4, 5.6716e-4, -4.2574e-4, 2.8431e-4};
  for (int n = 1; n <= 4; ++n) EXPECT_TRUE(near_relative(solution.position(n * pi / 100), printed[n - 1], 1e-4));
  // DY = r·cos45 as tested by Code_Aster (SPEC §2.5).
  EXPECT_TRUE(near_relative(solution.position(pi / 100) * std::cos(pi / 4), -5.0104e-4, 1e-4));
  ASSERT_EQ(solution.extremum_count(), 6);  // r(t7) = 1.47e-6 is the first below c = 7.07e-5
  EXPECT_NEAR(solution.extremum_value(6), 1.47e-6, 5e-9);
  expect_sdnd100_recurrence(solution, mu_effective * 10 / 1e4);
}

// ---------------------------------------------------------------------------------------------------
// Special cases

TEST(CoulombOscillator, ForceBelowFrictionThresholdNeverMoves) {
  for (const double tau : {0.0, 0.07}) {
    CoulombOscillator model = sdnv104(tau);
    model.force = 20000;  // < μN = 21000 N, and stays below it at every λ of the ramp
    const CoulombOscillatorSolution solution(model, 3.5);
    for (double t = 0; t <= 3.5; t += 0.01) {
      EXPECT_EQ(solution.position(t), 0.0) << "t = " << t;
      EXPECT_EQ(solution.velocity(t), 0.0) << "t = " << t;
    }
    EXPECT_EQ(solution.extremum_count(), 0);
    ASSERT_TRUE(solution.comes_to_rest());
    EXPECT_EQ(solution.rest_time(), 0.0);
    EXPECT_EQ(solution.rest_position(), 0.0);
  }
}

TEST(CoulombOscillator, FrictionlessIsTheHarmonicStepResponse) {
  CoulombOscillator model = sdnv104(0.0);
  model.mu = 0;
  const double t_end = 20.0;
  const CoulombOscillatorSolution solution(model, t_end);
  const double w = std::sqrt(model.stiffness / model.mass), static_x = model.force / model.stiffness;
  for (double t = 0; t <= t_end; t += 0.013)
    EXPECT_NEAR(solution.position(t), static_x * (1 - std::cos(w * t)), 1e-13 * static_x) << "t = " << t;
  const int half_periods = static_cast<int>(t_end * w / pi);
  ASSERT_EQ(solution.extremum_count(), half_periods);
  for (int n = 1; n <= half_periods; ++n) {
    EXPECT_NEAR(solution.extremum_time(n), n * pi / w, 1e-13 * n);
    EXPECT_NEAR(solution.extremum_value(n), n % 2 == 1 ? 2 * static_x : 0.0, 1e-13 * static_x);
  }
  EXPECT_FALSE(solution.comes_to_rest());
  EXPECT_THROW(solution.rest_time(), std::logic_error);
  EXPECT_THROW(solution.rest_position(), std::logic_error);
}

TEST(CoulombOscillator, InitialVelocity) {
  // Free mass (F = 0) launched from x = 0: harmonic about −f/k while moving up.
  // ω = 2 rad/s; f = μN = 2 N, c = f/k = 0.25 m
  const CoulombOscillator model{.mass = 2, .stiffness = 8, .normal_force = 10, .mu = 0.2, .v0 = 3};
  const CoulombOscillatorSolution solution(model, 20.0);
  const double w = 2, c = 0.25;
  const double t = 0.3;
  EXPECT_TRUE(near_relative(solution.position(t), -c + c * std::cos(w * t) + 3 / w * std::sin(w * t), 1e-14));
  const double first = -c + std::hypot(c, 3 / w);
  ASSERT_GE(solution.extremum_count(), 2);
  EXPECT_TRUE(near_relative(solution.extremum_value(1), first, 1e-14));
  EXPECT_NEAR(solution.extremum_time(1), std::atan2(3 / w, c) / w, 1e-14);  // x + c = R cos(ωt − φ)
  double r = first;
  for (int n = 2; n <= solution.extremum_count(); ++n) {
    r = -(r - 2 * c * (r > 0 ? 1 : -1));
    EXPECT_TRUE(near_relative(solution.extremum_value(n), r, 1e-12)) << "extremum " << n;
  }
  ASSERT_TRUE(solution.comes_to_rest());
  EXPECT_LE(std::abs(solution.rest_position()), c);
}

// A long ramp (several periods) with an initial offset: the mass slips, stops, sticks while the load
// grows and slips again, all during the ramp. The exact solution must follow the integrator.
TEST(CoulombOscillator, StickAndReleaseDuringALongRampAgreeWithRk4) {
  // f = μN = 0.8 N
  const CoulombOscillator model{.mass = 1, .stiffness = 1, .force = 1, .normal_force = 2, .mu = 0.4, .ramp_time = 20, .x0 = 0.3};
  const double t_end = 40;
  const CoulombOscillatorSolution solution(model, t_end);
  const NumericalSolution numerical = integrate_rk4(model, t_end, 1e-5);
  ASSERT_EQ(static_cast<int>(numerical.stops.size()), solution.extremum_count());
  ASSERT_GE(solution.extremum_count(), 3);
  for (int n = 1; n <= solution.extremum_count(); ++n) {
    EXPECT_TRUE(near_relative(solution.extremum_time(n), numerical.stops[n - 1].time, 1e-7)) << "extremum " << n;
    EXPECT_NEAR(solution.extremum_value(n), numerical.stops[n - 1].position, 1e-7) << "extremum " << n;
  }
  ASSERT_EQ(numerical.at_rest, solution.comes_to_rest());
  if (numerical.at_rest) {
    EXPECT_NEAR(solution.rest_position(), numerical.rest_position, 1e-7);
  }
  // Some stick phase during the ramp must have been crossed for this test to mean anything.
  bool stuck_then_moved = false;
  for (int n = 1; n < solution.extremum_count(); ++n) {
    const double t = solution.extremum_time(n) + 1e-3;
    if (solution.velocity(t) == 0.0 && t < model.ramp_time) stuck_then_moved = true;
  }
  EXPECT_TRUE(stuck_then_moved);
}

// From rest under a ramp the slip velocity c1·(1 − cos ωt) only touches zero every period: the mass does
// not stop there (acceleration and velocity vanish together), so there is no extremum during the ramp.
TEST(CoulombOscillator, SlipFromRestUnderALongRampOnlyTouchesZeroVelocity) {
  // ω = 1: about 8 periods of the ramp
  const CoulombOscillator model{.force = 1, .normal_force = 1, .mu = 0.5, .ramp_time = 50};
  const CoulombOscillatorSolution solution(model, 60);
  const double c1 = (model.force - model.mu * model.normal_force) / model.ramp_time;  // m/s
  for (double t = 0; t < model.ramp_time; t += 0.37)
    EXPECT_NEAR(solution.position(t), c1 * (t - std::sin(t)), 1e-14) << "t = " << t;
  ASSERT_GE(solution.extremum_count(), 1);
  EXPECT_GT(solution.extremum_time(1), model.ramp_time);
}

// F → −F, x0 → −x0, v0 → −v0 mirrors the motion.
TEST(CoulombOscillator, MirrorSymmetry) {
  const CoulombOscillator model{.force = 1, .normal_force = 2, .mu = 0.4, .ramp_time = 20, .x0 = 0.3, .v0 = 0.1};
  CoulombOscillator mirrored = model;
  mirrored.force = -model.force;
  mirrored.x0 = -model.x0;
  mirrored.v0 = -model.v0;
  const CoulombOscillatorSolution solution(model, 40), mirror(mirrored, 40);
  ASSERT_EQ(solution.extremum_count(), mirror.extremum_count());
  for (int n = 1; n <= solution.extremum_count(); ++n) {
    EXPECT_EQ(solution.extremum_time(n), mirror.extremum_time(n));
    EXPECT_EQ(solution.extremum_value(n), -mirror.extremum_value(n));
  }
  for (double t = 0; t <= 40; t += 0.1) EXPECT_NEAR(solution.position(t), -mirror.position(t), 1e-15);
}

// Random models (ramps up to several periods long, sticks, initial offsets and velocities, forces below
// and above the threshold): the exact positions must follow the numerical integration.
TEST(CoulombOscillator, RandomModelsAgreeWithRk4) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double t_end = 80;
  std::vector<double> sample_times;
  for (double t = 0; t <= t_end; t += 0.731) sample_times.push_back(t);
  for (int i = 0; i < 100; ++i) {
    CoulombOscillator model;
    model.mass = 0.5 + unit(random);
    model.stiffness = 0.5 + unit(random);
    model.force = 2 * unit(random) - 0.5;
    model.normal_force = unit(random);
    model.mu = unit(random);
    model.ramp_time = 60 * unit(random);
    model.x0 = unit(random) < 0.5 ? 0.0 : unit(random) - 0.5;
    model.v0 = unit(random) < 0.7 ? 0.0 : unit(random) - 0.5;
    const CoulombOscillatorSolution solution(model, t_end);
    const NumericalSolution numerical = integrate_rk4(model, t_end, 2e-3, sample_times);
    const double scale = 1e-3 + std::abs(model.force) / model.stiffness + std::abs(model.x0) +
                         std::abs(model.v0) / solution.natural_frequency();  // m
    for (std::size_t k = 0; k < sample_times.size(); ++k)
      ASSERT_NEAR(solution.position(sample_times[k]), numerical.samples[k], 1e-8 * scale)
          << "case " << i << ", t = " << sample_times[k];
    // Every extremum is a real one: the mass reverses or stays put, it does not slide on in the same
    // direction (which a velocity that merely touches zero would give).
    for (int n = 1; n <= solution.extremum_count(); ++n) {
      const double t = solution.extremum_time(n), dt = 1e-6;
      if (t + dt > t_end) break;
      EXPECT_LE(solution.velocity(t - dt) * solution.velocity(t + dt), 0.0) << "case " << i << ", extremum " << n;
    }
  }
}

TEST(CoulombOscillator, VelocityIsZeroAtEveryExtremum) {
  const CoulombOscillatorSolution solution(sdnv104(0.07), 9.0);
  const double speed_scale = 15.0 * std::sqrt(24000.0 / 7000.0);
  for (int n = 1; n <= solution.extremum_count(); ++n)
    EXPECT_NEAR(solution.velocity(solution.extremum_time(n)), 0.0, 1e-14 * speed_scale);
}

TEST(CoulombOscillator, QueriesOutOfRangeThrowWithAClearMessage) {
  const CoulombOscillatorSolution solution(sdnv104(0.0), 3.5);
  EXPECT_EQ(solution.extremum_count(), 2);  // x3 comes at 3T = 5.09 s > t_end
  EXPECT_FALSE(solution.comes_to_rest());
  for (const int index : {0, 3, -1}) {
    try {
      solution.extremum_time(index);
      ADD_FAILURE() << "no exception for index " << index;
    } catch (const std::out_of_range& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("index " + std::to_string(index)), std::string::npos) << message;
      EXPECT_NE(message.find("2 extrema"), std::string::npos) << message;
    }
  }
  EXPECT_THROW(solution.extremum_value(3), std::out_of_range);
  EXPECT_THROW(solution.position(-1e-9), std::out_of_range);
  EXPECT_THROW(solution.velocity(3.6), std::out_of_range);
  EXPECT_NO_THROW(solution.position(3.5));
  CoulombOscillator bad = sdnv104(0.0);
  bad.mass = 0;
  EXPECT_THROW(CoulombOscillatorSolution(bad, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace csim
