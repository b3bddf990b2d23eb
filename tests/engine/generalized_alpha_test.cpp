// The nonsmooth generalized-α stepper (engine/steppers/generalized_alpha.h): its coefficients, its
// limit ρ∞ = 1 (the trapezoidal rule, Moreau–Jean θ = ½), second order on the rigid SDNV104 shoe, no
// energy created under ρ∞ < 1, the elastic shoe at dt = 0.01 within 1e-4 of the exact ramped solution
// with far less chatter of its contact force than θ = ½, and what it refuses.
#include "engine/steppers/generalized_alpha.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"
#include "tools/scene/scene_error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace csim {
namespace {

const std::string kScenes = CSIM_SOURCE_DIR "/scenes/";

TEST(GeneralizedAlphaCoefficients, ChungHulbertAtBothEnds) {
  const GeneralizedAlphaCoefficients trapezoid(1.0);
  EXPECT_DOUBLE_EQ(trapezoid.alpha_m, 0.5);
  EXPECT_DOUBLE_EQ(trapezoid.alpha_f, 0.5);
  EXPECT_DOUBLE_EQ(trapezoid.gamma, 0.5);
  EXPECT_DOUBLE_EQ(trapezoid.beta, 0.25);
  EXPECT_DOUBLE_EQ(trapezoid.acceleration_weight(), 1.0);
  const GeneralizedAlphaCoefficients damped(0.0);
  EXPECT_DOUBLE_EQ(damped.alpha_m, -1.0);
  EXPECT_DOUBLE_EQ(damped.alpha_f, 0.0);
  EXPECT_DOUBLE_EQ(damped.gamma, 1.5);
  EXPECT_DOUBLE_EQ(damped.beta, 1.0);
  for (double rho : {0.0, 0.5, 0.9, 0.95}) {  // second order: γ = ½ − α_m + α_f; β ≥ γ/2 (stable)
    const GeneralizedAlphaCoefficients k(rho);
    EXPECT_NEAR(k.gamma, 0.5 - k.alpha_m + k.alpha_f, 1e-15);
    EXPECT_GE(k.beta, 0.5 * k.gamma);
  }
}

double relative_error(const RunReport& report, const std::string& check) {
  for (const CheckResult& c : report.checks)
    if (c.name == check) {
      EXPECT_TRUE(c.evaluated) << check << ": " << c.note;
      return c.error / c.reference;
    }
  ADD_FAILURE() << "no check " << check;
  return NAN;
}

RunReport run(const std::string& scene, std::vector<std::string> overrides) {
  return run_scene(*load_scene(kScenes + scene + "/scene.yaml", overrides), {});
}

// At ρ∞ = 1 the scheme is the trapezoidal rule, which Moreau–Jean θ = ½ is on a linear system: the
// same extrema of the elastic shoe, and the bar's energy kept to round-off. The two order their
// arithmetic differently, and θ = ½'s normal force rings undamped at this step
// (docs/generalized-alpha.md), which carries a round-off difference of 1e-14 in the first steps to a
// few 1e-9 in these errors; a different scheme (θ = 0.51) is 2e-3 away. One difference of rule: a
// contact within the touching band (contact_stage.h) has its gap read as 0 by Moreau–Jean and closed
// by generalized-α, and the shoe's ringing nodes sit in that band: x2 parts by 8e-7.
TEST(GeneralizedAlpha, RhoOneIsMoreauJeanThetaOneHalf) {
  const std::vector<std::string> shoe{"time.step=0.01", "time.end=4", "parameters.divisions=5"};
  std::vector<std::string> alpha = shoe, theta = shoe;
  alpha.insert(alpha.end(), {"integrator.type=generalized-alpha", "integrator.rho_infinity=1"});
  theta.push_back("integrator.theta=0.5");
  const RunReport a = run("sdnv104-quad4", alpha), b = run("sdnv104-quad4", theta);
  EXPECT_NEAR(relative_error(a, "x1"), relative_error(b, "x1"), 2e-8);
  EXPECT_NEAR(relative_error(a, "x2"), relative_error(b, "x2"), 2e-6);

  const RunReport bar = run("fe-free-vibration", {"integrator.type=generalized-alpha", "integrator.rho_infinity=1"});
  const EnergyBalance& e = bar.state.energy;
  EXPECT_NEAR(e.kinetic + e.elastic, e.initial_kinetic + e.initial_elastic, 1e-12 * e.initial_kinetic);
}

// Second order on the rigid shoe (lumped: a rigid body, two springs, Coulomb friction): the
// extrema's errors fall by about 16 when the step falls by 4. Moreau–Jean θ = 0.51 (first order)
// falls by about 4 on the same runs, so the bound below tells the two apart.
TEST(GeneralizedAlpha, SecondOrderOnTheRigidShoe) {
  for (const char* rho : {"integrator.rho_infinity=0.95", "integrator.rho_infinity=0.5"}) {
    const std::vector<std::string> common{"integrator.type=generalized-alpha", rho, "time.end=4"};
    std::vector<std::string> coarse = common, fine = common;
    coarse.push_back("time.step=0.01");
    fine.push_back("time.step=0.0025");
    const RunReport a = run("sdnv104-rigid", coarse), b = run("sdnv104-rigid", fine);
    for (const char* check : {"x1", "x2"}) {
      const double ratio = std::abs(relative_error(a, check) / relative_error(b, check));
      EXPECT_GE(ratio, 10.0) << rho << " " << check << ": order " << std::log2(ratio) / 2;
    }
  }
}

// What a run does step by step: the mechanical energy less the work of the loads (J), and the
// contact's total normal force (N), after each step.
struct History {
  std::vector<double> energy, normal_force;
  double initial = 0.0;
};

History step_through(const std::string& scene_name, const std::vector<std::string>& overrides) {
  const auto scene = load_scene(kScenes + scene_name + "/scene.yaml", overrides);
  const std::unique_ptr<Stepper> stepper = make_stepper(scene->world, scene->run);
  State state = initial_state(scene->world);
  stepper->initialize(state);
  History history;
  history.initial = state.energy.initial_kinetic + state.energy.initial_elastic;
  for (long k = 0; k < scene->run.steps; ++k) {
    stepper->step(state);
    const EnergyBalance& e = state.energy;
    history.energy.push_back(e.kinetic + e.elastic - e.work_of_loads);
    double normal = 0.0;
    for (const ActiveContact& c : state.contacts) normal += c.impulse(0);
    history.normal_force.push_back(normal / scene->run.step);
  }
  return history;
}

// ρ∞ < 1 removes energy and never adds any: at every step the bar's energy, and the falling ball's
// kinetic energy less the work of gravity, stay at or below their initial values (the ball through its
// elastic and partly elastic impacts).
TEST(GeneralizedAlpha, NoEnergyCreatedBelowRhoOne) {
  for (const char* rho : {"integrator.rho_infinity=0.95", "integrator.rho_infinity=0.5", "integrator.rho_infinity=0"}) {
    const History bar = step_through("fe-free-vibration", {"integrator.type=generalized-alpha", rho});
    EXPECT_LE(*std::max_element(bar.energy.begin(), bar.energy.end()), bar.initial * (1.0 + 1e-12)) << rho;
    EXPECT_LT(bar.energy.back(), bar.initial * (1.0 - 1e-7)) << rho;  // and it does remove some
    for (const char* e : {"parameters.restitution=1", "parameters.restitution=0.5"}) {
      const History ball = step_through(
          "bouncing-ball", {"integrator.type=generalized-alpha", rho, e, "time.step=1e-4"});
      const double largest = *std::max_element(ball.energy.begin(), ball.energy.end());
      // J: the ball's initial energy is 0 (at rest) and its drop is m g h0 = 9.81 J.
      EXPECT_LE(largest, 1e-12 * 9.81) << rho << " " << e;
    }
  }
}

// The median over the run of |N_{k+1} − 2 N_k + N_{k−1}| / N: the step-to-step oscillation of the
// contact force (θ = ½ leaves a period-two oscillation of about 1 % that nothing damps).
double chatter(const History& history, double from_step) {
  std::vector<double> second;
  const std::vector<double>& N = history.normal_force;
  for (std::size_t k = static_cast<std::size_t>(from_step); k + 1 < N.size(); ++k)
    second.push_back(std::abs(N[k + 1] - 2.0 * N[k] + N[k - 1]) / 70e3);
  std::nth_element(second.begin(), second.begin() + second.size() / 2, second.end());
  return second[second.size() / 2];
}

// The elastic shoe at dt = 0.01 (issue 32's target): x1 and x2 within 1e-4 of the exact ramped
// rigid-shoe solution at ρ∞ = 0.95, QUAD4 5 × 5 to 40 × 40 and QUAD8, and a contact force that
// oscillates from step to step at least 5 times less than under θ = ½. The ratio is a property of the
// trajectory, which round-off steers: with the top pressure moved by 1e-9 to 3e-9 Pa (1e-14 of it),
// six runs gave 36.3 on 5 × 5, 20.4–21.3 on 20 × 20 and 7.4–8.7 on 40 × 40, where an earlier bound
// of 8 held or failed with the last bits of the contact solve (docs/generalized-alpha.md). At the
// default 0.8 the contact nodes' drift, the header's limit, costs x2 up to 3e-4 on these meshes
// (docs/generalized-alpha.md).
TEST(GeneralizedAlpha, ElasticShoeAtALargeStepWithoutChatter) {
  const std::pair<const char*, const char*> shoes[] = {{"sdnv104-quad4", "parameters.divisions=5"},
                                                       {"sdnv104-quad4", "parameters.divisions=20"},
                                                       {"sdnv104-quad4", "parameters.divisions=40"},
                                                       {"sdnv104-quad8", "parameters.divisions=5"},
                                                       {"sdnv104-quad8", "parameters.divisions=10"}};
  for (const auto& [scene, mesh] : shoes) {
    const std::vector<std::string> common{"time.step=0.01", "time.end=4", mesh};
    std::vector<std::string> alpha = common, theta = common;
    alpha.insert(alpha.end(), {"integrator.type=generalized-alpha", "integrator.rho_infinity=0.95"});
    theta.push_back("integrator.theta=0.5");
    const RunReport report = run(scene, alpha);
    for (const char* check : {"x1", "x2"})
      EXPECT_LE(std::abs(relative_error(report, check)), 1e-4) << scene << " " << mesh << " " << check;
    const double alpha_chatter = chatter(step_through(scene, alpha), 20);
    const double theta_chatter = chatter(step_through(scene, theta), 20);
    EXPECT_LE(alpha_chatter, 0.2 * theta_chatter) << scene << " " << mesh << ": " << alpha_chatter << " against " << theta_chatter;
  }
}

// At small steps the shoe's elastic modes near ωh ~ 1 are excited by the contact switches and rock the
// corner node whose displacement the checks read; the default ρ∞ = 0.8 damps them enough that x2 stays
// within 1e-5, where ρ∞ = 0.95 lets a ringing extremum pass for x2 (3.3 relative) at this step.
TEST(GeneralizedAlpha, ElasticShoeAtASmallStepWithTheDefault) {
  const RunReport report = run("sdnv104-quad4", {"integrator.type=generalized-alpha", "time.step=1e-4", "time.end=4"});
  for (const char* check : {"x1", "x2"}) EXPECT_LE(std::abs(relative_error(report, check)), 1e-5) << check;
}

void expect_refused(const std::string& scene, const std::string& what) {
  try {
    load_scene(kScenes + scene + "/scene.yaml", {"integrator.type=generalized-alpha"});
    FAIL() << scene << ": expected a refusal";
  } catch (const SceneError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(what), std::string::npos) << message;
    EXPECT_NE(message.find("moreau-jean"), std::string::npos) << message;
    EXPECT_NE(message.find("integrator.type"), std::string::npos) << message;
  }
}

TEST(GeneralizedAlpha, RefusesWhatItDoesNotIntegrate) {
  expect_refused("incline-3d", "3D rigid bodies");
  expect_refused("spinning-bar", "finite-strain");
  expect_refused("sdnd100-a", "linear constraints");
  expect_refused("ssnv503-2d", "quasi-static");
  // Rayleigh damping with a spring: C no longer shares the modes of M and K, W would be nonsymmetric.
  std::ifstream source(kScenes + "fe-damped-drift/scene.yaml");
  std::stringstream text;
  text << source.rdbuf() << "\nsprings:\n  hold: {body: bar, point: [1, 0], stiffness: 1000, direction: [1, 0]}\n";
  const std::string file = testing::TempDir() + "/damped-with-spring.yaml";
  std::ofstream(file) << text.str();
  try {
    load_scene(file, {"integrator.type=generalized-alpha"});
    FAIL() << "expected a refusal";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("Rayleigh damping on a single body without springs"), std::string::npos) << e.what();
  }
}

// A check of the energy balance cannot fail under generalized-alpha (its numerical dissipation closes
// it): it is not evaluated, and the run does not pass.
TEST(GeneralizedAlpha, ABalanceCheckIsNotEvaluated) {
  const RunReport report = run("fe-free-vibration", {"integrator.type=generalized-alpha", "parameters.theta=0.6"});
  bool seen = false;
  for (const CheckResult& c : report.checks)
    if (c.name == "balance_closes") {
      seen = true;
      EXPECT_FALSE(c.evaluated);
      EXPECT_NE(c.note.find("generalized-alpha"), std::string::npos) << c.note;
    }
  EXPECT_TRUE(seen);
  EXPECT_FALSE(report.passed());
}

}  // namespace
}  // namespace csim
