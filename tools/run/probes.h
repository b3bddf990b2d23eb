// Evaluation of the scene's probes on a State (see scene.h for their definitions).
//   displacement  dir·(p(q) − p(q_ref)) of a material point (m);  position  dir·p(q) (m); on an
//                 elastic body a point between nodes moves as its element's shape functions
//                 interpolate (located once, here);
//   velocity      one velocity component (m/s or rad/s);  energy  a term of the balance (J), or
//                 mechanical = kinetic + elastic;
//   contact_force the resultant of a contact law's impulses / h on its first body (N): normal
//                 (compressive positive), tangential (2D: along e_z × n with n pointing into that
//                 body; 3D: magnitude), or a world component;
//   contact_count the number of a law's points that carry a normal force (closed), or of those in stick
//                 or in slip;
//   reaction      the generalized force a prescribed component's motion takes (N or N·m: a hub's
//                 torque), quasi-static stepper.
// Every probe but energy may carry a scale: its value is multiplied by it (a normalization such as
// a spin in units of v/R).
#pragma once

#include "engine/state.h"
#include "fem/point_location.h"

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace csim {

struct ProbeDefinition;  // scene.h
struct RunSettings;
struct World;            // world.h

class ProbeEvaluator {
 public:
  ProbeEvaluator(const World& world, const RunSettings& run);
  void evaluate(const State& state, std::vector<double>& values) const;
  // The same for the probes listed in `only` (their indices); the others' entries are left as they
  // were (values sized to the probes).
  void evaluate(const State& state, std::vector<double>& values, const std::vector<int>& only) const;
  bool reads_energy() const;  // whether a probe reads a term of State::energy (Stepper::measure_energy)

 private:
  // A probe's energy term or force component, resolved once from its name: a probe is evaluated at
  // every step, so no string is compared there.
  enum class Term { kinetic, elastic, mechanical, work, contact_dissipation, numerical_dissipation,
                    damping_dissipation, sleep_dissipation, balance };
  enum class Component { normal, x, y, z, direction, tangential, closed, stick, slip };

  double unscaled(std::size_t i, const State& state) const;
  double contact_force(std::size_t i, const State& state) const;

  const World& world_;
  const RunSettings& run_;
  std::vector<Eigen::Vector3d> reference_points_;  // world position at q_ref of each probe's point
  // Each probe's point as an element point, when it is a point of an elastic body that is not a node.
  std::vector<std::optional<MeshPoint>> element_points_;
  std::vector<Term> terms_;                        // each probe's, when it is an energy probe
  std::vector<Component> components_;              // each probe's, when it is a contact probe
};

}  // namespace csim
