// A loaded scene: the World it describes plus how to run it (time window, integrator, contact solver,
// probes, checks, output rate). Produced by load_scene(); see docs/contract.md for the file contract.
#pragma once

#include "tools/scene/scene_node.h"
#include "tools/output/vtk_data_array.h"
#include "contact/pgs_solver.h"
#include "engine/steppers/ida_parameters.h"
#include "engine/steppers/integrator.h"
#include "engine/steppers/generalized_alpha_parameters.h"
#include "engine/steppers/moreau_jean_parameters.h"
#include "engine/steppers/quasi_static_parameters.h"
#include "engine/world.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace csim {

// A named time series sampled every step.
struct ProbeDefinition {
  enum class Kind { displacement, position, velocity, energy, contact_force, contact_count, reaction };
  std::string name;
  Kind kind = Kind::displacement;
  int body = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();      // body frame (m)
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX(); // unit; the component measured
  int velocity_index = -1;                              // velocity probes
  std::string energy_term;                              // kinetic, elastic, work, contact_dissipation, numerical_dissipation, balance
  int contact_law = -1;                                 // contact_force probes: force on the law's first body
  std::string force_component;                          // normal, tangential, x, y, z; contact_count: closed, stick, slip
  double scale = 1.0;                                   // the value is multiplied by it (a normalization)
  std::string undefined;  // non-empty: the probe has no value for these parameters (why; its scale is NaN)
};

// What a check compares with its reference.
struct CheckDefinition {
  enum class Mode { at, extremum, maximum, minimum, extremum_time, final_value, mean };
  std::string name;
  int probe = -1;
  Mode mode = Mode::final_value;
  double time = 0.0;         // Mode::at (s); Mode::mean: the window's start (s)
  double time_end = 0.0;     // Mode::mean: the window's end (s)
  int index = 0;             // extremum index, from 1
  std::string reference;     // expression text ('=' stripped) or a number; may use t (the check's time)
                             // and initial (the probe's value at t = 0)
  int reference_line = 0;
  double absolute_tolerance = 0.0;
  double relative_tolerance = 0.0;
  std::string kind;          // analytical | literature | non-regression
  std::string source;
  bool enabled = true;       // false when only_if evaluates to 0, or cannot be evaluated, for these parameters
  std::string only_if;
  std::string exclusion;     // why it is not enabled
  std::string unjudgeable;   // non-empty: it applies but cannot be judged for these parameters (why)
};

// Newton's method of the steppers that iterate (quasi-static; Moreau–Jean with finite-strain bodies).
struct NewtonSettings {
  double tolerance = 1e-10;  // dimensionless: on the increment over the largest body's bounding radius
  int max_iterations = 30;
};

// How to run a scene. Every setting is held once; make_stepper (tools/run/run.h) composes the chosen
// stepper's parameters from them. The options of an integrator other than the chosen one keep their
// defaults (the loader refuses them when given: scene_loader.cpp).
struct RunSettings {
  Integrator integrator = Integrator::moreau_jean;
  double end_time = 1.0;        // s
  double step = 1e-3;           // s, the step used: time.step, shortened to divide the window
                                // (IDA: the interval between probe samples)
  double requested_step = 0.0;  // s, time.step as written
  long steps = 0;               // end_time / step, exactly
  PgsParameters contact_solver;
  double failure_residual = 1e-6;  // contact_solver.failure_residual: a solve left above it stops the run
  DelassusChoice delassus_storage = DelassusChoice::automatic;  // contact_solver.storage (iteration_operator.h)
  NewtonSettings newton;
  MoreauJeanOptions moreau_jean;   // integrator.theta, close_gaps
  GeneralizedAlphaOptions generalized_alpha;  // integrator.rho_infinity
  IdaOptions ida;                  // integrator.rtol, atol, penalty_*, epsilon, linear_solver, max_step(s)
  QuasiStaticOptions quasi_static; // integrator.contact_distance, max_cutbacks
  double output_rate = 0.0;  // s between rows of probes.csv; 0 = every step
  // output.paraview: how the ParaView files store their arrays; none: no ParaView files.
  std::optional<VtkEncoding> paraview = VtkEncoding::binary;
  bool body_poses = false;  // output.bodies: DIR/bodies.csv, the moving bodies' poses (body_poses.h)
  // output.shapes: DIR/paraview/bodies_NNNNNN.vtp, the shapes of the bodies that are not elastic
  // (body_shapes.h), in the encoding of output.paraview (which may not be none then).
  bool shapes = false;
  std::vector<ProbeDefinition> probes;
  std::vector<CheckDefinition> checks;
};

// The parameters of each stepper, composed from the settings.
MoreauJeanParameters moreau_jean_parameters(const RunSettings& run);
GeneralizedAlphaParameters generalized_alpha_parameters(const RunSettings& run);
IdaParameters ida_parameters(const RunSettings& run);
QuasiStaticParameters quasi_static_parameters(const RunSettings& run);

struct Scene {
  SceneDocument document;
  std::string name;          // the scene folder's name
  std::string description;
  std::string declared_integrator;  // integrator.type as the file writes it, before --set ("" when absent)
  World world;
  RunSettings run;
};

// Reads, validates and builds a scene; the overrides (KEY=VALUE) are applied first. Throws SceneError.
std::unique_ptr<Scene> load_scene(const std::string& file, const std::vector<std::string>& overrides);

// The effective configuration (file + overrides + defaults) as YAML text.
std::string dump_config(const Scene& scene);

}  // namespace csim
