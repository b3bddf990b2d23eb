// load_scene: parameters come first (every value may refer to them), then references (checks call
// them), then bodies (everything else names bodies), then what acts on them, then how to run.
#include "tools/scene/scene.h"
#include "tools/scene/scene_parts.h"

#include <cmath>
#include <filesystem>
#include <sstream>

namespace csim {

namespace {

void read_time_and_integrator(const SceneNode& root, RunSettings& run) {
  const SceneNode time = root.child("time");
  time.allow_only({"end", "step"});
  run.end_time = time.positive("end");
  MoreauJeanParameters& mj = run.moreau_jean;
  mj.step = time.positive("step");
  if (mj.step > run.end_time) time.fail_at("step", "the step is longer than the time window");
  // The step count is an integer that a double holds exactly (t = k h stays meaningful).
  const double count = std::ceil(run.end_time / mj.step - 1e-9);
  if (!(count <= 9007199254740992.0)) {
    std::ostringstream what;
    what << "time.end / time.step = " << run.end_time / mj.step << " steps, more than 2^53: use a longer step";
    time.fail_at("step", what.str());
  }
  run.steps = static_cast<long>(count);
  // The last step lands on time.end: a step that does not divide the window is shortened uniformly
  // (to time.end / steps, reported in summary.json beside the requested one), not overshot.
  run.requested_step = mj.step;
  if (std::abs(static_cast<double>(run.steps) * mj.step - run.end_time) > 1e-9 * mj.step)
    mj.step = run.end_time / static_cast<double>(run.steps);

  // Every integrator's settings are read (with their defaults) whatever the type, so that
  // `--set integrator.type=ida --set integrator.rtol=1e-8` works on any scene.
  const SceneNode integrator = root.section("integrator");
  integrator.allow_only({"type", "theta", "rtol", "atol", "penalty_stiffness", "penalty_damping", "epsilon",
                         "linear_solver", "max_step", "max_steps", "contact_distance", "newton_tolerance",
                         "newton_max_iterations", "max_cutbacks", "close_gaps"});
  run.integrator = integrator.string("type", "moreau-jean");
  if (run.integrator != "moreau-jean" && run.integrator != "ida" && run.integrator != "ida-events" &&
      run.integrator != "quasi-static")
    integrator.fail_at("type", "unknown integrator '" + run.integrator +
                                   "' (available: moreau-jean, quasi-static, ida, ida-events)");
  mj.theta = integrator.number("theta", 0.5);
  if (mj.theta < 0.5 || mj.theta > 1.0) integrator.fail_at("theta", "theta must lie in [0.5, 1]");
  mj.close_gaps = integrator.boolean("close_gaps", true);
  IdaParameters& ida = run.ida;
  ida.sample_step = mj.step;
  ida.events = run.integrator == "ida-events";
  ida.rtol = integrator.number("rtol", 1e-6);
  if (!(ida.rtol > 0.0)) integrator.fail_at("rtol", "must be > 0");
  ida.atol = integrator.number("atol", 1e-8);
  if (!(ida.atol > 0.0)) integrator.fail_at("atol", "must be > 0");
  ida.penalty_stiffness = integrator.non_negative("penalty_stiffness", 0.0);
  ida.penalty_damping = integrator.number("penalty_damping", -1.0);
  ida.epsilon = integrator.number("epsilon", 1e-6);
  if (!(ida.epsilon > 0.0)) integrator.fail_at("epsilon", "the regularization velocity must be > 0");
  ida.linear_solver = integrator.string("linear_solver", "auto");
  if (ida.linear_solver != "auto" && ida.linear_solver != "dense" && ida.linear_solver != "klu")
    integrator.fail_at("linear_solver", "expected auto, dense or klu");
  run.quasi_static.contact_distance = integrator.non_negative("contact_distance", 0.0);
  run.quasi_static.newton_tolerance = integrator.number("newton_tolerance", 1e-10);
  if (!(run.quasi_static.newton_tolerance > 0.0)) integrator.fail_at("newton_tolerance", "must be > 0");
  run.quasi_static.newton_max_iterations = static_cast<int>(integrator.whole_number("newton_max_iterations", 30, 1));
  run.quasi_static.max_cutbacks = static_cast<int>(integrator.whole_number("max_cutbacks", 4, 0, 30));
  mj.newton_tolerance = run.quasi_static.newton_tolerance;  // Moreau–Jean's Newton (finite-strain bodies)
  mj.newton_max_iterations = run.quasi_static.newton_max_iterations;
  ida.max_step = integrator.non_negative("max_step", 0.0);
  ida.max_steps = integrator.whole_number("max_steps", 1000000, 1, std::numeric_limits<long>::max());

  const SceneNode solver = root.section("contact_solver");
  solver.allow_only({"tolerance", "max_iterations", "omega", "failure_residual"});
  mj.solver.tolerance = solver.number("tolerance", 1e-12);
  if (!(mj.solver.tolerance > 0.0)) solver.fail_at("tolerance", "must be > 0");
  mj.solver.max_iterations = static_cast<int>(solver.whole_number("max_iterations", 1000, 1));
  mj.solver.omega = solver.number("omega", 1.0);
  if (!(mj.solver.omega > 0.0 && mj.solver.omega < 2.0)) solver.fail_at("omega", "must lie in (0, 2)");
  mj.failure_residual = solver.number("failure_residual", 1e-6);
  if (!(mj.failure_residual >= mj.solver.tolerance))
    solver.fail_at("failure_residual", "must be >= contact_solver.tolerance");
  run.quasi_static.step = mj.step;
  run.quasi_static.solver = mj.solver;
  run.quasi_static.failure_residual = mj.failure_residual;
}

void read_output(const SceneNode& root, RunSettings& run) {
  const SceneNode output = root.section("output");
  output.allow_only({"rate"});
  run.output_rate = output.non_negative("rate", run.end_time / 1000.0);
}

// The combinations of integrator and scene that an integrator cannot run are refused here, before the
// first step, so that validate and run give the same answer (the steppers' own unsupported()).
void refuse_unsupported(const SceneNode& root, const Scene& scene) {
  const SceneNode integrator = root.section("integrator");
  const std::string& type = scene.run.integrator;
  std::string refusal;
  if (type == "ida" || type == "ida-events") {
    if (scene.declared_integrator == "quasi-static")
      refusal = type + " integrates the inertia of a dynamic problem, and this scene is quasi-static (its file "
                       "sets integrator.type: quasi-static, its masses are placeholders); use quasi-static, or "
                       "moreau-jean with integrator.theta=1 for a damped transient";
    else
      refusal = IdaIntegrator::unsupported(scene.world, scene.run.ida);
  } else if (type == "quasi-static") {
    refusal = QuasiStatic::unsupported(scene.world);
  }
  if (!refusal.empty()) integrator.fail_at("type", refusal);
}

std::string scene_name(const std::string& file) {
  const std::filesystem::path path(file);
  if (path.filename() == "scene.yaml" && path.has_parent_path())
    return path.parent_path().filename().string();
  return path.stem().string();
}

}  // namespace

namespace {

// Builds the scene from its (overridden) document; reading fills the defaults into the tree.
void build_scene(Scene* scene) {
  const SceneNode root(scene->document.root, "", &scene->document, 1);
  root.allow_only({"description", "dimension", "parameters", "references", "gravity", "materials", "bodies", "springs",
                   "loads", "constraints", "contacts", "time", "integrator", "contact_solver", "probes",
                   "checks", "output"});
  scene->description = root.string("description", "");
  scene_parts::read_parameters(root, scene->document);
  scene_parts::read_references(root, scene->document);

  World& world = scene->world;
  const double dimension = root.number("dimension");
  if (dimension != 2 && dimension != 3) root.fail_at("dimension", "must be 2 or 3");
  world.dimension = static_cast<int>(dimension);
  if (root.has("gravity")) world.gravity = root.vector("gravity", world.dimension, world.dimension);
  else scene->document.root["gravity"] = std::vector<double>(world.dimension, 0.0);

  scene_parts::read_materials(root);
  scene_parts::read_bodies(root, world);
  scene_parts::read_springs(root, world);
  scene_parts::read_loads(root, world);
  scene_parts::read_constraints(root, world);
  scene_parts::read_contacts(root, world);

  read_time_and_integrator(root, scene->run);
  // Penalty friction keeps a per-contact history that only the quasi-static stepper carries.
  for (const ContactLaw& law : world.contact_laws)
    if (law.elastic_slip > 0.0 && scene->run.integrator != "quasi-static")
      root.child("contacts").child(law.name).fail_at(
          "elastic_slip", "penalty friction is implemented by the quasi-static stepper only (integrator.type is '" +
                              scene->run.integrator + "')");
  refuse_unsupported(root, *scene);
  read_output(root, scene->run);
  scene_parts::read_probes(root, world, scene->run);
  scene_parts::read_checks(root, scene->run);
}

bool key_exists(const YAML::Node& root, const std::string& assignment) {
  const std::string path = assignment.substr(0, assignment.find('='));
  YAML::Node node = root;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = path.find('.', start);
    const std::string key = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (!node.IsMap() || !node[key].IsDefined()) return false;
    if (dot == std::string::npos) return true;
    node.reset(node[key]);
    start = dot + 1;
  }
}

}  // namespace

// Overrides may name any key of the effective configuration, including one left to its default
// (`--set integrator.rtol=1e-8` on a scene that does not write it): those are applied to the tree
// of a first reading, which holds every default.
std::unique_ptr<Scene> load_scene(const std::string& file, const std::vector<std::string>& overrides) {
  auto scene = std::make_unique<Scene>();
  scene->document = load_scene_document(file);
  scene->name = scene_name(file);
  if (const YAML::Node& root = scene->document.root; root.IsMap() && root["integrator"].IsDefined()) {
    const YAML::Node integrator = root["integrator"];
    if (integrator.IsMap() && integrator["type"].IsDefined() && integrator["type"].IsScalar())
      scene->declared_integrator = integrator["type"].Scalar();
  }
  std::vector<std::string> on_defaults;
  for (const std::string& assignment : overrides) {
    scene_parts::check_parameter_override(scene->document, assignment);
    if (key_exists(scene->document.root, assignment)) apply_override(scene->document, assignment);
    else on_defaults.push_back(assignment);
  }
  if (!on_defaults.empty()) {
    Scene first;
    first.document.file = scene->document.file;
    first.document.root = YAML::Clone(scene->document.root);
    first.name = scene->name;
    first.declared_integrator = scene->declared_integrator;
    build_scene(&first);
    scene->document.root = first.document.root;
    for (const std::string& assignment : on_defaults) apply_override(scene->document, assignment);
  }
  build_scene(scene.get());
  return scene;
}

std::string dump_config(const Scene& scene) {
  YAML::Emitter out;
  out << scene.document.root;
  return std::string(out.c_str()) + "\n";
}

}  // namespace csim
