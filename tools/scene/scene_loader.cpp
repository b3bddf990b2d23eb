// load_scene: parameters come first (every value may refer to them), then references (checks call
// them), then bodies (everything else names bodies), then what acts on them, then how to run.
#include "tools/scene/scene.h"
#include "tools/scene/integrator_keys.h"
#include "tools/scene/scene_parts.h"
#include "engine/steppers/generalized_alpha.h"
#include "engine/steppers/ida_integrator.h"
#include "engine/steppers/quasi_static.h"

#include <cmath>
#include <filesystem>
#include <sstream>

namespace csim {

namespace {

void read_time(const SceneNode& root, RunSettings& run) {
  const SceneNode time = root.child("time");
  time.allow_only({"end", "step"});
  run.end_time = time.positive("end");
  run.step = time.positive("step");
  if (run.step > run.end_time) time.fail_at("step", "the step is longer than the time window");
  // The step count is an integer that a double holds exactly (t = k h stays meaningful).
  const double count = std::ceil(run.end_time / run.step - 1e-9);
  if (!(count <= 9007199254740992.0)) {
    std::ostringstream what;
    what << "time.end / time.step = " << run.end_time / run.step << " steps, more than 2^53: use a longer step";
    time.fail_at("step", what.str());
  }
  run.steps = static_cast<long>(count);
  // The last step lands on time.end: a step that does not divide the window is shortened uniformly
  // (to time.end / steps, reported in summary.json beside the requested one), not overshot.
  run.requested_step = run.step;
  if (std::abs(static_cast<double>(run.steps) * run.step - run.end_time) > 1e-9 * run.step)
    run.step = run.end_time / static_cast<double>(run.steps);
}

// Refuses the integrator keys that the chosen integrator ignores (the rule: integrator_keys.h),
// and drops from the tree those of the file's own integrator when --set chose another, so that the
// effective configuration (dump-config) holds only keys that take effect.
void refuse_ignored_keys(const SceneNode& integrator, Integrator chosen, const GivenIntegratorKeys& given) {
  const std::string chosen_name = integrator_name(chosen);
  const auto refuse = [&](const std::string& key, bool by_set) {
    std::string readers;
    for (Integrator other : kIntegrators)
      if (integrator_reads(other, key)) readers += (readers.empty() ? "" : ", ") + integrator_name(other);
    const std::string message = "ignored by the " + chosen_name + " integrator (integrator.type), which does not read it (" +
                                readers + " do" + (readers.find(',') == std::string::npos ? "es" : "") + "); " +
                                (by_set ? "drop --set integrator." + key : "remove it from the scene") +
                                ", or choose an integrator that reads it with integrator.type";
    if (by_set)  // no line of the file to point at, as for the other --set errors
      throw SceneError(integrator.document().file, 0, "integrator." + key, message);
    integrator.fail_at(key, message);
  };
  for (const std::string& key : given.set)
    if (is_integrator_key(key) && !integrator_reads(chosen, key)) refuse(key, true);
  if (!integrator.is_map()) return;
  std::vector<std::string> dropped;
  for (const auto& [key, node] : integrator.entries()) {
    if (!is_integrator_key(key) || integrator_reads(chosen, key)) continue;
    const bool of_declared = given.declared && integrator_reads(*given.declared, key);
    if (given.written.count(key) && !of_declared) refuse(key, false);
    dropped.push_back(key);  // the file's own integrator's, --set chose another
  }
  YAML::Node map = integrator.yaml();
  for (const std::string& key : dropped) map.remove(key);
}

void read_integrator(const SceneNode& root, RunSettings& run, const GivenIntegratorKeys& given) {
  const SceneNode integrator = root.section("integrator");
  integrator.allow_only(integrator_section_keys());
  const std::string type = integrator.string("type", integrator_name(Integrator::moreau_jean));
  const std::optional<Integrator> chosen = integrator_from_name(type);
  if (!chosen) integrator.fail_at("type", "unknown integrator '" + type + "' (available: " + integrator_names() + ")");
  run.integrator = *chosen;
  refuse_ignored_keys(integrator, run.integrator, given);

  // Only the chosen integrator's keys are read (and their defaults written into the tree).
  const auto reads = [&](const char* key) { return integrator_reads(run.integrator, key); };
  // The defaults are the options' own (moreau_jean_parameters.h, generalized_alpha_parameters.h).
  if (reads("theta")) {
    const MoreauJeanOptions defaults;
    run.moreau_jean.theta = integrator.number("theta", defaults.theta);
    if (run.moreau_jean.theta < 0.5 || run.moreau_jean.theta > 1.0)
      integrator.fail_at("theta", "theta must lie in [0.5, 1]");
    run.moreau_jean.close_gaps = integrator.boolean("close_gaps", defaults.close_gaps);
    run.moreau_jean.sleep.speed = integrator.non_negative("sleep_speed", defaults.sleep.speed);
    run.moreau_jean.sleep.time = integrator.non_negative("sleep_time", defaults.sleep.time);
  }
  if (reads("rho_infinity")) {
    run.generalized_alpha.rho_infinity = integrator.number("rho_infinity", GeneralizedAlphaOptions{}.rho_infinity);
    if (!(run.generalized_alpha.rho_infinity >= 0.0 && run.generalized_alpha.rho_infinity <= 1.0))
      integrator.fail_at("rho_infinity", "rho_infinity must lie in [0, 1]");
  }
  if (reads("rtol")) {
    IdaOptions& ida = run.ida;
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
    ida.max_step = integrator.non_negative("max_step", 0.0);
    ida.max_steps = integrator.whole_number("max_steps", 1000000, 1, std::numeric_limits<long>::max());
  }
  if (reads("contact_distance")) {
    run.quasi_static.contact_distance = integrator.non_negative("contact_distance", 0.0);
    run.quasi_static.max_cutbacks = static_cast<int>(integrator.whole_number("max_cutbacks", 4, 0, 30));
  }
  if (reads("newton_tolerance")) {
    run.newton.tolerance = integrator.number("newton_tolerance", 1e-10);
    if (!(run.newton.tolerance > 0.0)) integrator.fail_at("newton_tolerance", "must be > 0");
    run.newton.max_iterations = static_cast<int>(integrator.whole_number("newton_max_iterations", 30, 1));
  }

  const SceneNode solver = root.section("contact_solver");
  solver.allow_only({"tolerance", "max_iterations", "omega", "failure_residual", "storage"});
  run.contact_solver.tolerance = solver.number("tolerance", 1e-12);
  if (!(run.contact_solver.tolerance > 0.0)) solver.fail_at("tolerance", "must be > 0");
  run.contact_solver.max_iterations = static_cast<int>(solver.whole_number("max_iterations", 1000, 1));
  // `auto` (the default, written into the tree as such: a first reading for a --set on a default
  // must not turn it into a given omega) or a number, used as it is (pgs_solver.h).
  run.contact_solver.relax_sparse = !solver.has("omega") || solver.child("omega").as_string() == "auto";
  if (run.contact_solver.relax_sparse) {
    solver.string("omega", "auto");
    run.contact_solver.omega = 1.0;
  } else {
    run.contact_solver.omega = solver.number("omega");
    if (!(run.contact_solver.omega > 0.0 && run.contact_solver.omega < 2.0))
      solver.fail_at("omega", "must be auto or lie in (0, 2)");
  }
  const std::string storage = solver.string("storage", "auto");
  if (storage == "auto") run.delassus_storage = DelassusChoice::automatic;
  else if (storage == "dense") run.delassus_storage = DelassusChoice::dense;
  else if (storage == "sparse") run.delassus_storage = DelassusChoice::sparse;
  else solver.fail_at("storage", "expected auto, dense or sparse");
  // Moreau–Jean and generalized-α store W by blocks (iteration_operator.h); the quasi-static stepper's
  // operator, over its reduced unknowns, only dense; the IDA integrators solve no contact problem.
  if (is_ida(run.integrator) && run.delassus_storage != DelassusChoice::automatic)
    solver.fail_at("storage", integrator_name(run.integrator) +
                                  " solves no contact problem (its contacts are regularized or events): remove "
                                  "the key, or use moreau-jean or generalized-alpha");
  if (run.integrator == Integrator::quasi_static && run.delassus_storage == DelassusChoice::sparse)
    solver.fail_at("storage", "quasi-static stores its Delassus operator dense (over its reduced unknowns): use "
                              "auto or dense, or moreau-jean or generalized-alpha for W stored by blocks");
  run.failure_residual = solver.number("failure_residual", 1e-6);
  if (!(run.failure_residual >= run.contact_solver.tolerance))
    solver.fail_at("failure_residual", "must be >= contact_solver.tolerance");
}

void read_output(const SceneNode& root, RunSettings& run) {
  const SceneNode output = root.section("output");
  output.allow_only({"rate", "paraview", "bodies", "shapes"});
  run.body_poses = output.boolean("bodies", false);
  run.shapes = output.boolean("shapes", false);
  run.output_rate = output.non_negative("rate", run.end_time / 1000.0);
  const std::string paraview = output.string("paraview", "binary");
  if (paraview == "binary") run.paraview = VtkEncoding::binary;
  else if (paraview == "zlib") run.paraview = VtkEncoding::zlib;
  else if (paraview == "ascii") run.paraview = VtkEncoding::ascii;
  else if (paraview == "none") run.paraview = std::nullopt;
  else output.fail_at("paraview", "expected binary, zlib, ascii or none, not '" + paraview + "'");
  if (run.paraview == VtkEncoding::zlib && !vtk_compression_available())
    output.fail_at("paraview", "this csim was built without zlib (Debian's zlib1g-dev): use binary or ascii");
  if (run.shapes && !run.paraview)
    output.fail_at("shapes", "the shapes are ParaView files, and output.paraview is none: set output.paraview to "
                             "binary, zlib or ascii, or output.shapes to false");
}

// The combinations of integrator and scene that an integrator cannot run are refused here, before the
// first step, so that validate and run give the same answer (the steppers' own unsupported()).
void refuse_unsupported(const SceneNode& root, const Scene& scene) {
  const SceneNode integrator = root.section("integrator");
  const Integrator type = scene.run.integrator;
  std::string refusal;
  if (is_ida(type) || type == Integrator::generalized_alpha) {
    if (scene.declared_integrator == integrator_name(Integrator::quasi_static))
      refusal = integrator_name(type) +
                " integrates the inertia of a dynamic problem, and this scene is quasi-static (its file "
                "sets integrator.type: quasi-static, its masses are placeholders); use quasi-static, or "
                "moreau-jean with integrator.theta=1 for a damped transient";
    else if (type == Integrator::generalized_alpha)
      refusal = GeneralizedAlpha::unsupported(scene.world);
    else
      refusal = IdaIntegrator::unsupported(scene.world, ida_parameters(scene.run));
  } else if (type == Integrator::quasi_static) {
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
void build_scene(Scene* scene, const GivenIntegratorKeys& given) {
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

  read_time(root, scene->run);
  read_integrator(root, scene->run, given);
  if (scene->run.integrator == Integrator::moreau_jean && scene->run.moreau_jean.sleep.enabled())
    for (const BodyInstance& b : world.bodies)
      if (b.body->nonlinear())
        root.child("integrator").fail_at(
            "sleep_speed", "sleeping bodies need a linear World, and body '" + b.name +
                               "' is finite-strain: remove integrator.sleep_speed (or set it to 0)");
  // Penalty friction keeps a per-contact history that only the quasi-static stepper carries.
  for (const ContactLaw& law : world.contact_laws)
    if (law.elastic_slip > 0.0 && scene->run.integrator != Integrator::quasi_static)
      root.child("contacts").child(law.name).fail_at(
          "elastic_slip", "penalty friction is implemented by the quasi-static stepper only (integrator.type is '" +
                              integrator_name(scene->run.integrator) + "')");
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
  GivenIntegratorKeys given;
  given.declared = Integrator::moreau_jean;
  YAML::Node root = scene->document.root;
  if (root.IsMap() && root["integrator"].IsDefined() && root["integrator"].IsMap()) {
    for (const auto& entry : root["integrator"]) {
      const std::string key = entry.first.as<std::string>();
      if (key != "type") given.written.insert(key);
      else if (entry.second.IsScalar()) {
        scene->declared_integrator = entry.second.Scalar();
        given.declared = integrator_from_name(scene->declared_integrator);
      }
    }
  }
  // integrator.type first, also where the file leaves it to its default: the other integrator keys,
  // and the defaults a first reading fills in, are the chosen integrator's.
  const std::string type_prefix = "integrator.type=";
  for (const std::string& assignment : overrides) {
    const std::string path = assignment.substr(0, assignment.find('='));
    if (path.rfind("integrator.", 0) == 0 && path != "integrator.type") given.set.insert(path.substr(11));
    if (assignment.rfind(type_prefix, 0) == 0 && root.IsMap() &&
        (!root["integrator"].IsDefined() || root["integrator"].IsMap()))
      root["integrator"]["type"] = assignment.substr(type_prefix.size());
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
    build_scene(&first, given);
    scene->document.root = first.document.root;
    for (const std::string& assignment : on_defaults) apply_override(scene->document, assignment);
  }
  build_scene(scene.get(), given);
  return scene;
}

std::string dump_config(const Scene& scene) {
  YAML::Emitter out;
  out << scene.document.root;
  return std::string(out.c_str()) + "\n";
}

}  // namespace csim
