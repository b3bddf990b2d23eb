// load_scene: parameters come first (every value may refer to them), then references (checks call
// them), then bodies (everything else names bodies), then what acts on them, then how to run.
#include "engine/scene/scene.h"
#include "engine/scene/scene_parts.h"

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

  const SceneNode integrator = root.section("integrator");
  integrator.allow_only({"type", "theta"});
  run.integrator = integrator.string("type", "moreau-jean");
  if (run.integrator != "moreau-jean")
    integrator.fail_at("type", "unknown integrator '" + run.integrator +
                                   "' (available: moreau-jean; ida and quasi-static are not built yet)");
  mj.theta = integrator.number("theta", 0.5);
  if (mj.theta < 0.5 || mj.theta > 1.0) integrator.fail_at("theta", "theta must lie in [0.5, 1]");

  const SceneNode solver = root.section("contact_solver");
  solver.allow_only({"tolerance", "max_iterations", "omega", "failure_residual"});
  mj.solver.tolerance = solver.number("tolerance", 1e-12);
  if (!(mj.solver.tolerance > 0.0)) solver.fail_at("tolerance", "must be > 0");
  const double iterations = solver.number("max_iterations", 1000);
  if (iterations < 1 || iterations != static_cast<int>(iterations))
    solver.fail_at("max_iterations", "must be a whole number >= 1");
  mj.solver.max_iterations = static_cast<int>(iterations);
  mj.solver.omega = solver.number("omega", 1.0);
  if (!(mj.solver.omega > 0.0 && mj.solver.omega < 2.0)) solver.fail_at("omega", "must lie in (0, 2)");
  mj.failure_residual = solver.number("failure_residual", 1e-6);
  if (!(mj.failure_residual >= mj.solver.tolerance))
    solver.fail_at("failure_residual", "must be >= contact_solver.tolerance");
}

void read_output(const SceneNode& root, RunSettings& run) {
  const SceneNode output = root.section("output");
  output.allow_only({"rate"});
  run.output_rate = output.non_negative("rate", run.end_time / 1000.0);
}

std::string scene_name(const std::string& file) {
  const std::filesystem::path path(file);
  if (path.filename() == "scene.yaml" && path.has_parent_path())
    return path.parent_path().filename().string();
  return path.stem().string();
}

}  // namespace

std::unique_ptr<Scene> load_scene(const std::string& file, const std::vector<std::string>& overrides) {
  auto scene = std::make_unique<Scene>();
  scene->document = load_scene_document(file);
  for (const std::string& assignment : overrides) apply_override(scene->document, assignment);
  scene->name = scene_name(file);

  const SceneNode root(scene->document.root, "", &scene->document, 1);
  root.allow_only({"description", "dimension", "parameters", "references", "gravity", "bodies", "springs",
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

  scene_parts::read_bodies(root, world);
  scene_parts::read_springs(root, world);
  scene_parts::read_loads(root, world);
  scene_parts::read_constraints(root, world);
  scene_parts::read_contacts(root, world);

  read_time_and_integrator(root, scene->run);
  read_output(root, scene->run);
  scene_parts::read_probes(root, world, scene->run);
  scene_parts::read_checks(root, scene->run);
  return scene;
}

std::string dump_config(const Scene& scene) {
  YAML::Emitter out;
  out << scene.document.root;
  return std::string(out.c_str()) + "\n";
}

}  // namespace csim
