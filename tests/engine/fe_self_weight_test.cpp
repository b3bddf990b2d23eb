// The weight of an elastic body with fixed nodes: the consistent body force ∫ Nᵀ ρ g dV over every node,
// whose free rows include the coupling M_fc g to the fixed nodes (fe_body.h).
//
// The clamped column: plane strain, ν = 0, width w, height L, 1 × ny quad4, its base clamped, under its
// own weight along −y. With ν = 0 (λ = 0) the 1D bar solution u_y(y) = ρ g (L y − y²/2) / E, u_x = 0 is
// the 2D one (σ_xx = σ_xy = 0: the x equations hold with u_x = 0), and the quad4 discretization of u_x
// = 0, u_y(y) piecewise linear is exactly the 2-node bar's, whose nodal values are exact for a
// consistent load (the bar's Green function is piecewise linear: Strang & Fix, An Analysis of the
// Finite Element Method, §1.2; Hughes, The Finite Element Method, §1.10). So the tip sags
// u(L) = ρ g L² / (2E) to round-off, whatever ny; dropping M_fc g (a load ρ g w h / 6 at the first
// free level, h = L / ny) made it 1/(3 ny²) short: 8.33 %, 2.08 %, 0.52 % for ny = 2, 4, 8.
#include "engine/bodies/fe_body.h"
#include "engine/dynamics.h"
#include "fem/assembly.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

namespace csim {
namespace {

constexpr double kYoung = 1.0e6, kDensity = 1000.0, kGravity = 10.0, kHeight = 1.0, kWidth = 0.5;

// u(L) = ρ g L² / (2E), m (downward).
constexpr double kTipSag = kDensity * kGravity * kHeight * kHeight / (2.0 * kYoung);

std::unique_ptr<Scene> load_text(const std::string& name, const std::string& text) {
  const std::string file = ::testing::TempDir() + name;
  { std::ofstream(file) << text; }
  return load_scene(file, {});
}

// Rayleigh damping α M (1/s) of the dynamic runs: the slowest mode, ω1 = π c / (2L) = 49.7 rad/s
// (c = √(E/ρ)), is damped at α / (2 ω1) = 1.0 of critical, the faster ones at the rate α / 2: over 10 s
// every mode's distance to the static state falls by e^-500 or more, and the static state (v = 0:
// K u = f) is each scheme's fixed point.
constexpr double kMassDamping = 100.0;

// The column with ny elements along its height, run by `integrator` (a scene's integrator map), with
// mass damping when damped.
std::string column(int ny, const std::string& integrator, const std::string& time = "{end: 1, step: 1}",
                   bool damped = false) {
  return "dimension: 2\n"
         "gravity: [0, " + std::to_string(-kGravity) + "]\n"
         "bodies:\n"
         "  column:\n"
         "    type: elastic\n"
         "    mesh: {generator: rectangle, size: [" + std::to_string(kWidth) + ", " + std::to_string(kHeight) +
         "], divisions: [1, " + std::to_string(ny) + "], element: quad4}\n"
         "    material: {young: " + std::to_string(kYoung) + ", poisson: 0, density: " + std::to_string(kDensity) + "}\n"
         "    fixed: {bottom: [x, y]}\n" +
         (damped ? "    damping: {alpha: " + std::to_string(kMassDamping) + "}\n" : std::string()) +
         "time: " + time + "\n"
         "integrator: " + integrator + "\n"
         "probes:\n"
         "  tip: {displacement: {body: column, node: top_right, component: y}}\n"
         "  side: {displacement: {body: column, node: top_right, component: x}}\n";
}

// The tip's sag and sideways motion at the end of the run, m.
std::pair<double, double> tip(int ny, const std::string& integrator, const std::string& time = "{end: 1, step: 1}",
                              bool damped = false) {
  const auto scene = load_text("csim_clamped_column.yaml", column(ny, integrator, time, damped));
  const RunReport report = run_scene(*scene, {});
  return {-report.samples.back()[0], report.samples.back()[1]};
}

// The sag's relative error tolerance: the nodal values are exact, and a solve of these few unknowns
// (condition number ∝ ny²) leaves round-off of about 1e-15 (measured: 8.7e-16 in every stepper);
// 1e-9 also covers IDA's Newton at rest, and is 5e6 times below the 1/(3 ny²) ≥ 0.52 % of the
// dropped coupling.
constexpr double kSagTolerance = 1e-9;

TEST(FeSelfWeight, ClampedColumnSagsAsTheBarUnderItsWeightQuasiStatically) {
  for (int ny : {2, 4, 8}) {
    const auto [sag, side] = tip(ny, "{type: quasi-static}");
    EXPECT_NEAR(sag, kTipSag, kSagTolerance * kTipSag) << "ny = " << ny << ": error " << sag / kTipSag - 1.0;
    EXPECT_NEAR(side, 0.0, kSagTolerance * kTipSag) << "ny = " << ny;
  }
}

TEST(FeSelfWeight, ClampedColumnComesToRestAtTheBarsSagUnderEveryDynamicIntegrator) {
  // From rest, damped to the static state (kMassDamping); h = 0.01 s. Moreau–Jean also undamped at
  // θ = 1 (backward Euler, which takes each mode's distance down by 1 / √(1 + (ω h)²) ≤ 0.89 a step).
  const std::vector<std::pair<std::string, bool>> runs = {{"{type: moreau-jean, theta: 1}", false},
                                                          {"{type: moreau-jean}", true},
                                                          {"{type: generalized-alpha}", true},
                                                          {"{type: ida}", true}};
  for (const auto& [integrator, damped] : runs)
    for (int ny : {2, 4, 8}) {
      const auto [sag, side] = tip(ny, integrator, "{end: 10, step: 0.01}", damped);
      EXPECT_NEAR(sag, kTipSag, kSagTolerance * kTipSag)
          << integrator << (damped ? " damped" : "") << ", ny = " << ny << ": error " << sag / kTipSag - 1.0;
      EXPECT_NEAR(side, 0.0, kSagTolerance * kTipSag) << integrator << ", ny = " << ny;
    }
}

TEST(FeSelfWeight, TheSmoothStageGivesEveryStepperTheConsistentWeight) {
  // Dynamics' external force, which Moreau–Jean, the quasi-static stepper, generalized-α and IDA all
  // take (dynamics.h): on the free nodes of the clamped column, ∫ N ρ g = −ρ g w h / 2 per node of an
  // inner level (two elements of w h, each giving a quarter of its weight to each of its nodes), and
  // −ρ g w h / 4 at the top. With M_ff alone the first free level got 5/6 of it.
  const int ny = 4;
  const auto scene = load_text("csim_clamped_column_weight.yaml", column(ny, "{type: quasi-static}"));
  const World& world = scene->world;
  const Dynamics dynamics(world);
  Vector f;
  dynamics.external(Vector::Zero(world.position_size), 0.0, f);
  const FeBody& body = *world.bodies[0].body->finite_elements();
  const double h = kHeight / ny, level = kDensity * kGravity * kWidth * h;  // an element's weight, N
  for (int node = 0; node < body.node_count(); ++node) {
    const Eigen::Vector3d x = body.node_reference(node);
    if (x.y() == 0.0) continue;  // clamped
    const bool top = std::abs(x.y() - kHeight) < 1e-12;
    EXPECT_NEAR(f(body.free_index(node, 1)), -(top ? 0.25 : 0.5) * level, 1e-12 * level) << "node at y = " << x.y();
    EXPECT_EQ(f(body.free_index(node, 0)), 0.0);
  }
  EXPECT_NEAR(f.sum(), -kDensity * kGravity * kWidth * (kHeight - 0.5 * h), 1e-12 * level);
}

TEST(FeSelfWeight, ClampedHexa8BlockCarriesItsWholeWeightOnItsSupport) {
  // A 1 × 1 × 1 m block, 2 × 2 × 2 hexa8, clamped on its base (z = 0), under its own weight. The support
  // reaction R = K u − M G on the clamped dofs (the force the clamp exerts, G the field g on every node)
  // must sum to the weight, upward: R_z = ρ V g. With M_ff alone the free nodes got the weight less
  // their coupling to the base, 1/(6 nz) of the whole: 11/12 for nz = 2.
  const std::string text = "dimension: 3\n"
                           "gravity: [0, 0, " + std::to_string(-kGravity) + "]\n"
                           "bodies:\n"
                           "  block:\n"
                           "    type: elastic\n"
                           "    mesh: {generator: box, size: [1, 1, 1], divisions: [2, 2, 2]}\n"
                           "    material: {young: " + std::to_string(kYoung) + ", poisson: 0.25, density: " +
                           std::to_string(kDensity) + "}\n"
                           "    fixed: {zmin: [x, y, z]}\n"
                           "time: {end: 1, step: 1}\n"
                           "integrator: {type: quasi-static}\n"
                           "probes:\n"
                           "  top: {displacement: {body: block, point: [1, 1, 1], component: z}}\n";
  const auto scene = load_text("csim_clamped_block.yaml", text);
  const RunReport report = run_scene(*scene, {});
  const BodyInstance& instance = scene->world.bodies[0];
  const FeBody& body = *instance.body->finite_elements();
  const FeModel model{body.mesh(), body.material(), body.thickness()};
  const Eigen::VectorXd u = body.full_displacement(instance.positions(report.state.q));
  Eigen::VectorXd field = Eigen::VectorXd::Zero(body.mesh().dof_count());
  for (int node = 0; node < body.node_count(); ++node) field(3 * node + 2) = -kGravity;
  const Eigen::VectorXd reaction = assemble_stiffness(model) * u - assemble_mass(model, false) * field;
  double carried = 0.0;  // N, upward
  for (int node = 0; node < body.node_count(); ++node)
    if (body.free_index(node, 2) < 0) carried += reaction(3 * node + 2);
  const double weight = kDensity * 1.0 * kGravity;
  EXPECT_NEAR(carried, weight, 1e-9 * weight) << "carried / weight = " << carried / weight;
}

}  // namespace
}  // namespace csim
