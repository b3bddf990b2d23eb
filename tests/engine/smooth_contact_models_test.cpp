// The two contact models of the smooth integrator on their own (engine/steppers/): the regularized
// model's force against its law (contact/regularized_law.h), and the event model's choice of stick or
// slip and the event function that signals the switch. The World: scenes/incline flattened (angle 0):
// a 10 kg, 0.2 m square block on its two bottom corners on a fixed halfspace, μ = 0.5, g = 9.81 m/s².
#include "engine/dynamics.h"
#include "engine/steppers/event_contact_model.h"
#include "engine/steppers/regularized_contact_model.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <gtest/gtest.h>

namespace csim {
namespace {

std::unique_ptr<Scene> flat_block() {
  return load_scene(CSIM_SOURCE_DIR "/scenes/incline/scene.yaml", {"parameters.angle=0"});
}

TEST(RegularizedContactModel, ForceOfTwoPenetratingSlidingCornersIsTheLaws) {
  const auto scene = flat_block();
  const World& world = scene->world;
  const Dynamics dynamics(world);
  const double k = 1e6, epsilon = 1e-3;  // N/m, m/s
  RegularizedContactModel model(dynamics, k, 0.0, epsilon, 1e-3);
  State state = initial_state(world);
  const int block = world.bodies[world.body_index("block")].velocity_offset;
  const double depth = 1e-6, speed = 0.1;  // m, m/s
  state.q(block + 1) -= depth;  // both corners sink by `depth`
  state.v(block) = speed;       // sliding along +x
  Vector f_contact;
  std::vector<ActiveContact> record;
  const Vector f_applied = Vector::Zero(world.velocity_size);
  model.force(0.0, state.q, state.v, f_applied, f_contact, &record);
  ASSERT_EQ(record.size(), 2u);
  // Per corner: F_n = k·depth = 1 N upwards on the block, F_t = −μ F_n u/√(u² + ε²) along x.
  const double normal = k * depth;
  const double friction = 0.5 * normal * speed / std::sqrt(speed * speed + epsilon * epsilon);
  EXPECT_NEAR(f_contact(block + 1), 2.0 * normal, 1e-9);
  EXPECT_NEAR(f_contact(block), -2.0 * friction, 1e-9);
  // The normal forces at x = ±0.1 m cancel in moment; the friction, −2F_t along x at 0.1 m below the
  // centre, turns it about z by r × F = (−0.1) · (−1) · (−2F_t)... = −0.1 · 2F_t (N·m).
  EXPECT_NEAR(f_contact(block + 2), -0.1 * 2.0 * friction, 1e-9);
  EXPECT_NEAR(model.stored_energy(), 2.0 * 0.5 * k * depth * depth, 1e-15);
  // Lifted clear of the surface: no force.
  state.q(block + 1) += 2 * depth;
  model.force(0.0, state.q, state.v, f_applied, f_contact, nullptr);
  EXPECT_EQ(f_contact.norm(), 0.0);
}

TEST(EventContactModel, ChoosesStickBelowTheThresholdAndSignalsTheSwitchAbove) {
  const auto scene = flat_block();
  const World& world = scene->world;
  const Dynamics dynamics(world);
  State state = initial_state(world);
  const Matrix inverse_mass = Matrix(dynamics.mass()).inverse();  // no constraints: P = M⁻¹
  EventContactModel model(world, state.q, inverse_mass, 1e-3);
  const int block = world.bodies[world.body_index("block")].velocity_offset;
  const double weight = 10.0 * 9.81, threshold = 0.5 * weight;  // N
  Vector f_applied = Vector::Zero(world.velocity_size);
  f_applied(block + 1) = -weight;

  f_applied(block) = 0.5 * threshold;  // pushed at half the friction threshold: stick
  model.choose_mode(0.0, state.q, state.v, f_applied);
  EXPECT_TRUE(model.sticking());
  Vector f_contact;
  model.force(0.0, state.q, state.v, f_applied, f_contact, nullptr);
  EXPECT_NEAR(f_contact(block), -0.5 * threshold, 1e-9);  // the reaction holds the push
  EXPECT_NEAR(f_contact(block + 1), weight, 1e-9);
  double g[2];
  model.events(0.0, state.q, state.v, f_applied, g);
  EXPECT_GT(g[0], 0.0);  // inside the cone

  f_applied(block) = 1.5 * threshold;  // the push grows past the threshold while sticking
  model.events(0.0, state.q, state.v, f_applied, g);
  EXPECT_LT(g[0], 0.0);  // the event function has crossed zero: a switch for IDA to locate
  model.choose_mode(0.0, state.q, state.v, f_applied);
  EXPECT_FALSE(model.sticking());
  model.force(0.0, state.q, state.v, f_applied, f_contact, nullptr);
  EXPECT_NEAR(f_contact(block), -threshold, 1e-9);  // sliding friction μ N against the push
  EXPECT_NEAR(f_contact(block + 1), weight, 1e-9);
}

}  // namespace
}  // namespace csim
