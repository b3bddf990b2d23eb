// probes (named time series) and checks (a probe against a reference, with a tolerance).
#include "engine/bodies/fe_body.h"
#include "tools/scene/scene_parts.h"

#include <limits>
#include <optional>
#include <sstream>

namespace csim::scene_parts {

namespace {

// A value that may not exist for these parameters (SceneNode::as_number_if_defined), with the reason.
std::optional<double> value_for_these_parameters(const SceneNode& node, std::string& why) {
  const std::optional<double> value = node.as_number_if_defined(why);
  if (value) return value;
  const std::string text = node.as_string();
  why = why.empty() ? "'" + text + "' is not finite for these parameters"
                    : "'" + text + "' has no value for these parameters: " + why;
  return std::nullopt;
}

bool is_expression(const SceneNode& node) { return node.is_scalar() && node.yaml().Scalar().starts_with('='); }

Eigen::Vector3d component_direction(const SceneNode& node, int dimension) {
  if (node.has("direction")) {
    const Eigen::Vector3d d = node.vector("direction", dimension, dimension);
    if (d.norm() == 0.0) node.fail_at("direction", "must not be zero");
    return d.normalized();
  }
  const std::string component = node.string("component");
  if (component == "x") return Eigen::Vector3d::UnitX();
  if (component == "y") return Eigen::Vector3d::UnitY();
  if (component == "z" && dimension == 3) return Eigen::Vector3d::UnitZ();
  node.fail_at("component", "expected x, y" + std::string(dimension == 3 ? " or z" : "") + " (or give a direction)");
}

ProbeDefinition read_probe(const std::string& name, const SceneNode& node, const World& world,
                           const RunSettings& run) {
  ProbeDefinition p;
  p.name = name;
  node.expect_map();
  const auto entries = node.entries();
  if (entries.size() != 1)
    node.fail("a probe has exactly one kind: displacement, position, velocity, energy, contact_force, contact_count or reaction");
  const auto& [kind, spec] = entries.front();
  const int d = world.dimension;
  if (kind == "displacement" || kind == "position") {
    spec.allow_only({"body", "point", "node", "component", "direction", "scale"});
    p.kind = kind == "position" ? ProbeDefinition::Kind::position : ProbeDefinition::Kind::displacement;
    p.body = body_named(spec, "body", world);
    if (spec.has("point")) p.point = spec.vector("point", d, d);
    if (spec.has("node")) p.point = node_point(spec, world.bodies[p.body]);
    // An elastic body's point between nodes moves with its element (probes.h); one outside every
    // element is no point of the body, and would read 0 for ever.
    const BodyInstance& b = world.bodies[p.body];
    if (const FeBody* fe = b.body->finite_elements(); fe && fe->node_at(p.point) < 0 && !fe->locate(p.point)) {
      std::ostringstream where;
      where << "(" << p.point.x() << ", " << p.point.y();
      if (d == 3) where << ", " << p.point.z();
      where << ")";
      spec.fail_at("point", "the point " + where.str() + " is outside every element of body '" + b.name +
                                "' (reference coordinates, m)");
    }
    p.direction = component_direction(spec, d);
  } else if (kind == "velocity" || kind == "reaction") {  // a reaction: of a prescribed component
    spec.allow_only({"body", "component", "scale"});
    p.kind = kind == "velocity" ? ProbeDefinition::Kind::velocity : ProbeDefinition::Kind::reaction;
    p.body = body_named(spec, "body", world);
    const BodyInstance& b = world.bodies[p.body];
    const std::string component = spec.string("component");
    const int local = b.body->velocity_index(component);
    if (kind == "velocity" && local < 0)
      spec.fail_at("component", "body '" + b.name + "' has no velocity component '" + component + "'");
    bool prescribed = false;
    for (const PrescribedComponent& c : world.prescribed) prescribed = prescribed || (c.body == p.body && c.component == local);
    if (kind == "reaction" && (local < 0 || !prescribed))
      spec.fail_at("component", "body '" + b.name + "' has no prescribed component '" + component + "'");
    p.velocity_index = b.velocity_offset + local;
  } else if (kind == "energy") {
    p.kind = ProbeDefinition::Kind::energy;
    p.energy_term = spec.as_string();
    const char* terms[] = {"kinetic",   "elastic", "mechanical", "work", "contact_dissipation", "numerical_dissipation",
                           "damping_dissipation", "sleep_dissipation", "balance"};
    bool known = false;
    for (const char* t : terms) known = known || p.energy_term == t;
    if (!known)
      spec.fail("unknown energy term (expected kinetic, elastic, mechanical, work, contact_dissipation, "
                "numerical_dissipation, damping_dissipation, sleep_dissipation or balance)");
    // The quasi-static stepper has no kinetic energy and does not account the work of prescribed
    // motions or friction's dissipation: these terms would read 0 and the balance the elastic energy.
    const bool stored = p.energy_term == "kinetic" || p.energy_term == "elastic" || p.energy_term == "mechanical";
    if (run.integrator == Integrator::quasi_static && !stored)
      spec.fail("integrator.type quasi-static accounts only the stored energy (elastic, kinetic = 0, mechanical), not '" +
                p.energy_term + "'; use moreau-jean or ida for this probe");

  } else if (kind == "contact_count") {
    spec.allow_only({"contact", "status"});
    p.kind = ProbeDefinition::Kind::contact_count;
    p.contact_law = contact_law_named(spec, "contact", world);
    p.force_component = spec.string("status", "closed");
    if (p.force_component != "closed" && p.force_component != "stick" && p.force_component != "slip")
      spec.fail_at("status", "expected closed, stick or slip");
  } else if (kind == "contact_force") {
    spec.allow_only({"contact", "component", "direction", "scale"});
    p.kind = ProbeDefinition::Kind::contact_force;
    p.contact_law = contact_law_named(spec, "contact", world);
    if (spec.has("direction")) {
      if (spec.has("component")) spec.fail("give either component or direction");
      p.direction = component_direction(spec, d);
      p.force_component = "direction";
    } else {
      p.force_component = spec.string("component");
    }
    const char* components[] = {"normal", "tangential", "x", "y", "z", "direction"};
    bool known = false;
    for (const char* c : components) known = known || p.force_component == c;
    if (!known) spec.fail_at("component", "expected normal, tangential, x, y or z (or give a direction)");
    // The force on the law's first side is the force on one body; a group's bodies push on each other.
    const ContactLaw& law = world.contact_laws[p.contact_law];
    if (law.body_a < 0 && p.force_component != "normal")
      spec.fail_at(spec.has("direction") ? "direction" : "component",
                   "contact law '" + law.name + "' names the group '" + world.groups[law.group_a].name +
                       "' first: only its normal force (the sum over its contacts) is defined; use component "
                       "normal, or a law whose first side is a body");
  } else {
    spec.fail("unknown probe kind '" + kind +
              "' (expected displacement, position, velocity, energy, contact_force, contact_count or reaction)");
  }
  if (spec.is_map() && spec.has("scale")) {
    const std::optional<double> scale = value_for_these_parameters(spec.child("scale"), p.undefined);
    p.scale = scale.value_or(std::numeric_limits<double>::quiet_NaN());
    if (!scale) p.undefined = "its scale " + p.undefined;
  }
  return p;
}

CheckDefinition read_check(const std::string& name, const SceneNode& node, const RunSettings& run,
                           const ExpressionScope& scope) {
  node.allow_only({"probe", "at", "extremum", "maximum", "minimum", "extremum_time", "final", "mean", "reference",
                   "tolerance", "kind", "source", "only_if"});
  CheckDefinition c;
  c.name = name;
  const std::string probe = node.string("probe");
  for (std::size_t i = 0; i < run.probes.size(); ++i)
    if (run.probes[i].name == probe) c.probe = static_cast<int>(i);
  if (c.probe < 0) node.fail_at("probe", "no probe named '" + probe + "'");
  // The generalized-α stepper's numerical dissipation is what closes its balance (generalized_alpha.h),
  // so a check of the balance could not fail: it is reported as not evaluated, never as passed.
  const ProbeDefinition& judged = run.probes[c.probe];
  if (run.integrator == Integrator::generalized_alpha && judged.kind == ProbeDefinition::Kind::energy &&
      judged.energy_term == "balance")
    c.unjudgeable = "integrator.type generalized-alpha keeps no independent energy balance (its numerical "
                    "dissipation is what closes it); judge the balance with moreau-jean or ida";

  int modes = 0;
  auto index_of = [&](const char* key) { return static_cast<int>(node.whole_number(key, std::nullopt, 1)); };
  // A time beyond time.end is not evaluated (checks.h); one that parameters put before t = 0 neither.
  if (node.has("at")) { ++modes; c.mode = CheckDefinition::Mode::at; c.time = node.number("at");
    if (c.time < 0 && !is_expression(node.child("at"))) node.fail_at("at", "must be >= 0");
    if (c.time < 0) c.unjudgeable = "its time " + std::to_string(c.time) + " s is before t = 0 for these parameters"; }
  if (node.has("extremum")) { ++modes; c.mode = CheckDefinition::Mode::extremum; c.index = index_of("extremum"); }
  if (node.has("maximum")) { ++modes; c.mode = CheckDefinition::Mode::maximum; c.index = index_of("maximum"); }
  if (node.has("minimum")) { ++modes; c.mode = CheckDefinition::Mode::minimum; c.index = index_of("minimum"); }
  if (node.has("extremum_time")) { ++modes; c.mode = CheckDefinition::Mode::extremum_time; c.index = index_of("extremum_time"); }
  if (node.has("final")) { ++modes; c.mode = CheckDefinition::Mode::final_value;
    if (!node.child("final").as_bool()) node.fail_at("final", "write final: true"); }
  if (node.has("mean")) { ++modes; c.mode = CheckDefinition::Mode::mean;
    const Eigen::Vector3d window = node.vector("mean", 2, 2);
    c.time = window(0);
    c.time_end = window(1);
    if (!(0.0 <= c.time && c.time < c.time_end)) {
      const std::vector<SceneNode> bounds = node.child("mean").items();
      if (!(is_expression(bounds[0]) || is_expression(bounds[1])))
        node.fail_at("mean", "expected [start, end] with 0 <= start < end");
      std::ostringstream why;
      why << "its window [" << c.time << ", " << c.time_end << "] s is empty or starts before t = 0 for these parameters";
      c.unjudgeable = why.str();
    } }
  if (modes != 1) node.fail("give exactly one of: at, extremum, maximum, minimum, extremum_time, final, mean");

  // The reference is checked now (names known, syntax) and evaluated after the run, with t bound.
  const SceneNode reference = node.child("reference");
  c.reference = reference.as_string();
  c.reference_line = reference.line();
  if (!c.reference.empty() && c.reference[0] == '=') {
    c.reference.erase(0, 1);
    try {
      for (const std::string& n : Expression::parse(c.reference).names())
        if (n != "t" && n != "initial" && !scope.variables.count(n) && !scope.functions.count(n))
          reference.fail("unknown name '" + n + "' (not a parameter, a reference function, t or initial)");
    } catch (const ExpressionError& e) {
      reference.fail(std::string("in expression: ") + e.what());
    }
  } else {
    reference.as_number();
  }

  const SceneNode tolerance = node.child("tolerance");
  tolerance.allow_only({"absolute", "relative"});
  if (!tolerance.has("absolute") && !tolerance.has("relative")) tolerance.fail("give absolute and/or relative");
  c.absolute_tolerance = tolerance.non_negative("absolute", 0.0);
  c.relative_tolerance = tolerance.non_negative("relative", 0.0);
  c.kind = node.string("kind");
  if (c.kind != "analytical" && c.kind != "literature" && c.kind != "non-regression")
    node.fail_at("kind", "expected analytical, literature or non-regression");
  c.source = node.string("source");
  if (node.has("only_if")) {
    const SceneNode condition = node.child("only_if");
    c.only_if = condition.as_string();
    std::string why;
    const std::optional<double> value = value_for_these_parameters(condition, why);
    c.enabled = value && *value != 0.0;
    if (!value) c.exclusion = "only_if could not be evaluated, counted as false: " + why;
    else if (!c.enabled) c.exclusion = "only_if '" + c.only_if + "' is false for these parameters";
  }
  return c;
}

}  // namespace

void read_probes(const SceneNode& root, const World& world, RunSettings& run) {
  if (!root.has("probes")) return;
  for (const auto& [name, node] : root.child("probes").entries())
    run.probes.push_back(read_probe(name, node, world, run));
}

void read_checks(const SceneNode& root, RunSettings& run) {
  if (!root.has("checks")) return;
  for (const auto& [name, node] : root.child("checks").entries())
    run.checks.push_back(read_check(name, node, run, root.document().scope));
}

}  // namespace csim::scene_parts
