// parameters: the physical inputs of a scene, each a number or an expression of the ones above it,
// or a text (a name such as mooney-rivlin: letters first, then letters, digits, '-' or '_') that a
// text-valued key reads as '=NAME';
// references: named analytical solutions built from them, callable in expressions as NAME.QUANTITY(…).
#include "tools/reference/coulomb_oscillator.h"
#include "tools/scene/scene_parts.h"

#include <algorithm>
#include <cctype>
#include <memory>

namespace csim::scene_parts {

namespace {

// A parameter's kind follows from how its value is spelt: a name is a text, anything else a number or
// an '=expression' (which as_number then checks).
bool spells_a_text(const std::string& value) {
  return !value.empty() && std::isalpha(static_cast<unsigned char>(value[0])) &&
         std::all_of(value.begin(), value.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_'; }) &&
         value != "inf" && value != "nan";
}

}  // namespace

void read_parameters(const SceneNode& root, SceneDocument& document) {
  if (!root.has("parameters")) return;
  for (const auto& [name, node] : root.child("parameters").entries()) {
    if (name == "t" || name == "pi" || name == "e")
      node.fail("'" + name + "' is a reserved name in expressions");
    const std::string text = node.is_scalar() ? node.yaml().Scalar() : std::string();
    if (spells_a_text(text)) document.scope.texts[name] = text;
    else document.scope.variables[name] = node.as_number();
  }
}

// Since the kind follows from the spelling, `--set parameters.mu=abc` would turn mu into a text and fail
// far away, where mu is used ("unknown name 'mu'"); the override is refused here, at its own key.
void check_parameter_override(const SceneDocument& document, const std::string& assignment) {
  const std::size_t equal = assignment.find('=');
  const std::string prefix = "parameters.";
  if (equal == std::string::npos || assignment.compare(0, prefix.size(), prefix) != 0) return;
  const std::string name = assignment.substr(prefix.size(), equal - prefix.size());
  const YAML::Node& root = document.root;
  const YAML::Node parameters = root["parameters"];
  if (!parameters.IsMap()) return;
  const YAML::Node old_value = parameters[name];
  if (!old_value.IsDefined() || !old_value.IsScalar()) return;  // apply_override names those
  const std::string value = assignment.substr(equal + 1);
  const bool was_text = spells_a_text(old_value.Scalar()), is_text = spells_a_text(value);
  if (was_text == is_text) return;
  const std::string expected = was_text ? "a name (letters first, then letters, digits, '-' or '_')"
                                        : "a number or an '=expression'";
  throw SceneError(document.file, old_value.Mark().line + 1, prefix + name,
                   "--set " + assignment + ": " + name + " is a " + (was_text ? "text" : "numeric") +
                       " parameter (" + old_value.Scalar() + " in the file), expected " + expected);
}

namespace {

void add_coulomb_oscillator(const std::string& name, const SceneNode& node, double end_time,
                            SceneDocument& document) {
  node.allow_only({"model", "mass", "stiffness", "force", "normal_force", "mu", "ramp_time",
                   "initial_position", "initial_velocity"});
  CoulombOscillator model;
  model.mass = node.positive("mass");
  model.stiffness = node.positive("stiffness");
  model.force = node.number("force", 0.0);
  model.normal_force = node.non_negative("normal_force", 0.0);
  model.mu = node.non_negative("mu", 0.0);
  model.ramp_time = node.non_negative("ramp_time", 0.0);
  model.x0 = node.number("initial_position", 0.0);
  model.v0 = node.number("initial_velocity", 0.0);
  // A little past the end, so that the last sample (t = steps·h) is inside the solution's window.
  std::shared_ptr<CoulombOscillatorSolution> solution;
  try {
    solution = std::make_shared<CoulombOscillatorSolution>(model, end_time * 1.01);
  } catch (const std::exception& e) {
    node.fail(std::string("cannot build the reference solution: ") + e.what());
  }
  auto index = [](std::span<const double> args) {
    if (args.size() != 1) throw ExpressionError("expects one argument (an index from 1)");
    return static_cast<int>(args[0]);
  };
  auto& f = document.scope.functions;
  f[name + ".extremum"] = [solution, index](std::span<const double> a) { return solution->extremum_value(index(a)); };
  f[name + ".extremum_time"] = [solution, index](std::span<const double> a) { return solution->extremum_time(index(a)); };
  f[name + ".extremum_count"] = [solution](std::span<const double>) { return double(solution->extremum_count()); };
  f[name + ".position"] = [solution](std::span<const double> a) {
    if (a.size() != 1) throw ExpressionError("position(t) expects one argument");
    return solution->position(a[0]);
  };
  f[name + ".velocity"] = [solution](std::span<const double> a) {
    if (a.size() != 1) throw ExpressionError("velocity(t) expects one argument");
    return solution->velocity(a[0]);
  };
  f[name + ".rest_position"] = [solution](std::span<const double>) { return solution->rest_position(); };
  f[name + ".rest_time"] = [solution](std::span<const double>) { return solution->rest_time(); };
}

}  // namespace

void read_references(const SceneNode& root, SceneDocument& document) {
  if (!root.has("references")) return;
  const double end_time = root.child("time").positive("end");
  for (const auto& [name, node] : root.child("references").entries()) {
    node.expect_map();
    const std::string model = node.string("model");
    if (model == "coulomb-oscillator") add_coulomb_oscillator(name, node, end_time, document);
    else node.fail_at("model", "unknown reference model '" + model + "' (available: coulomb-oscillator)");
  }
}

}  // namespace csim::scene_parts
