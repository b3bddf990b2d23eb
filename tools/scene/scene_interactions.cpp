// springs, loads, constraints and contacts: what acts on the bodies.
#include "engine/bodies/fe_body.h"
#include "engine/contact_stage/contact_law_table.h"
#include "tools/scene/scene_parts.h"
#include "fem/assembly.h"

#include <unordered_map>

namespace csim::scene_parts {

namespace {

Eigen::Vector3d point(const SceneNode& node, const std::string& key, int dimension) {
  return node.has(key) ? node.vector(key, dimension, dimension) : Eigen::Vector3d::Zero();
}

// A spring or a point load on an elastic body acts at a node: at another point it would act on
// nothing (FeBody::point_jacobian has no columns there), so it is refused.
void expect_node(const SceneNode& node, const std::string& key, const BodyInstance& body, const Eigen::Vector3d& at,
                 bool node_key = false) {
  const FeBody* fe = body.body->finite_elements();
  if (!fe || fe->node_at(at) >= 0) return;
  node.fail_at(key, "on the elastic body '" + body.name + "' this acts at a node: give a node's reference coordinates" +
                        std::string(node_key ? ", or `node:` a one-node set of its mesh" : ""));
}

}  // namespace

// A spring: {body, point | node, other (default: the ground), other_point, stiffness, direction}.
// On an elastic body the attachment is a node: `node` names a one-node set of its mesh.
void read_springs(const SceneNode& root, World& world) {
  if (!root.has("springs")) return;
  const int d = world.dimension;
  for (const auto& [name, node] : root.child("springs").entries()) {
    node.allow_only({"body", "point", "node", "other", "other_point", "stiffness", "direction"});
    Spring s;
    s.name = name;
    s.body_a = body_named(node, "body", world);
    s.point_a = point(node, "point", d);
    if (node.has("node")) s.point_a = node_point(node, world.bodies[s.body_a]);
    expect_node(node, "point", world.bodies[s.body_a], s.point_a, true);
    if (node.has("other")) {
      s.body_b = body_named(node, "other", world);
      if (world.bodies[s.body_b].body->fixed()) s.body_b = -1;  // a fixed body is the ground
      s.point_b = point(node, "other_point", d);
      if (s.body_b >= 0) expect_node(node, "other_point", world.bodies[s.body_b], s.point_b);
    }
    s.stiffness = node.positive("stiffness");
    if (node.has("direction")) {
      s.direction = node.vector("direction", d, d);
      if (s.direction.norm() == 0.0) node.fail_at("direction", "must not be zero");
      s.direction.normalize();
    }
    if (world.bodies[s.body_a].body->fixed()) node.fail_at("body", "the first body of a spring must move");
    world.springs.push_back(s);
  }
}

// A load: {body, point, force, ramp (s) | table [[t, λ], ...]}, or on an elastic body a uniform
// pressure (Pa, positive into the body) on a face set: {body, pressure, faces, ramp | table}.
void read_loads(const SceneNode& root, World& world) {
  if (!root.has("loads")) return;
  const int d = world.dimension;
  for (const auto& [name, node] : root.child("loads").entries()) {
    node.allow_only({"body", "point", "force", "pressure", "faces", "ramp", "table"});
    Load load;
    load.name = name;
    load.body = body_named(node, "body", world);
    if (world.bodies[load.body].body->fixed()) node.fail_at("body", "a load on a fixed body does nothing");
    if (node.has("pressure")) {
      const FeBody* body = world.bodies[load.body].body->finite_elements();
      if (!body) node.fail_at("pressure", "a pressure acts on the faces of an elastic body");
      if (node.has("force") || node.has("point")) node.fail("give either pressure and faces, or force and point");
      const std::string faces = node.string("faces");
      if (!body->mesh().face_sets.count(faces)) node.fail_at("faces", "the mesh has no face set '" + faces + "'");
      const FeModel model{body->mesh(), body->material(), body->thickness()};
      load.nodal_forces = body->restrict(pressure_load(model, body->mesh().face_sets.at(faces), node.number("pressure")));
    } else {
      load.point = point(node, "point", d);
      expect_node(node, "point", world.bodies[load.body], load.point);
      load.force = node.vector("force", d, d);
    }
    if (node.has("ramp") && node.has("table")) node.fail("give either ramp or table, not both");
    // Read ramp (and so record its default in the tree) only without a table: a default ramp next to
    // the file's table would make the tree that --set on a default key re-reads contradict itself.
    if (node.has("table")) {
      read_table_rows(node.child("table"), load.multiplier.table);
      if (load.multiplier.table.empty()) node.fail_at("table", "must not be empty");
    } else {
      load.multiplier.ramp_time = node.non_negative("ramp", 0.0);
    }
    world.loads.push_back(load);
  }
}

void read_table_rows(const SceneNode& list, std::vector<std::pair<double, double>>& table) {
  for (const SceneNode& row : list.items()) {
    const Eigen::Vector3d entry = row.as_vector(2, 2);
    if (!table.empty() && entry(0) <= table.back().first) row.fail("table times must increase");
    table.emplace_back(entry(0), entry(1));
  }
}

// A linear constraint: {terms: {BODY.COMPONENT: coefficient, ...}, value (m)}.
void read_constraints(const SceneNode& root, World& world) {
  if (!root.has("constraints")) return;
  for (const auto& [name, node] : root.child("constraints").entries()) {
    node.allow_only({"terms", "value"});
    LinearConstraint c;
    c.name = name;
    for (const auto& [term, coefficient] : node.child("terms").entries()) {
      const std::size_t dot = term.rfind('.');
      const int body = dot == std::string::npos ? -1 : world.body_index(term.substr(0, dot));
      if (body < 0) coefficient.fail("expected BODY.COMPONENT with a known body");
      const BodyInstance& b = world.bodies[body];
      const int local = b.body->velocity_index(term.substr(dot + 1));
      if (local < 0) coefficient.fail("body '" + b.name + "' has no component '" + term.substr(dot + 1) + "'");
      c.terms.emplace_back(b.velocity_offset + local, coefficient.as_number());
    }
    if (c.terms.empty()) node.fail_at("terms", "a constraint needs at least one term");
    c.value = node.number("value", 0.0);
    world.constraints.push_back(c);
  }
}

namespace {

// What the contact checks need of a side (a body, or a group's bodies), formed once per group so that
// reading L laws is O(L) however large the groups.
struct SideSummary {
  std::string name;                // "body 'a'" or "group 'G'"
  int count = 0;                   // bodies
  int without_shapes = -1;         // a body with neither shapes nor an elastic surface, or −1
  std::vector<int> elastic;        // its first two elastic bodies
  int hull_shaped = -1;            // a body with a capsule, cylinder, convex or mesh shape, or −1
};

SideSummary summarize(const World& world, int body, int group) {
  SideSummary side;
  side.name = group >= 0 ? "group '" + world.groups[group].name + "'" : "body '" + world.bodies[body].name + "'";
  for (int b : side_bodies(world, body, group)) {
    ++side.count;
    const BodyInstance& instance = world.bodies[b];
    if (instance.body->elastic()) {
      if (side.elastic.size() < 2) side.elastic.push_back(b);
    } else if (instance.shapes.empty() && side.without_shapes < 0) {
      side.without_shapes = b;
    }
    for (const ShapeInstance& shape : instance.shapes)
      if (side.hull_shaped < 0 && (std::holds_alternative<Capsule>(shape.shape) ||
                                   std::holds_alternative<Cylinder>(shape.shape) ||
                                   std::holds_alternative<Convex>(shape.shape) ||
                                   std::holds_alternative<TriangleMesh>(shape.shape)))
        side.hull_shaped = b;
  }
  return side;
}

// Two distinct elastic bodies, one from each side (−1, −1 if none): a pair the law would make.
std::pair<int, int> elastic_pair(const SideSummary& a, const SideSummary& b) {
  for (int x : a.elastic)
    for (int y : b.elastic)
      if (x != y) return {x, y};
  return {-1, -1};
}

}  // namespace

// A contact law: {between: [A, B], mu: μ | [μ1, μ2], friction_direction, restitution, features,
// mu_ramp: [start, end] (s; μ grows linearly from 0 over that window), elastic_slip: γ (m, quasi-static
// stepper only; 0 = exact stick)}.
// A and B each name a body or a group (a body's `group`): the law pairs every body of A with every
// distinct body of B; [G, G] pairs every two bodies of G. A law naming two bodies overrides one naming
// a group, and one naming a body and a group overrides one naming two groups (contact_law_table.h).
// features (with an elastic body): nodes (its boundary nodes on the other body's shapes, node-to-
// surface), faces (the other body's sphere or box vertices on its boundary faces, so that a rigid body
// can land on it), both, or smoothed (plane scenes: Gauss points on a smooth curve through its boundary
// nodes, Catmull–Rom on quad4 boundaries, the quadratic edges of quad8, against the other body's
// shapes; deformable_surface.h, boundary_curve.h).
void read_contacts(const SceneNode& root, World& world) {
  if (!root.has("contacts")) return;
  // Names → bodies and groups, and each group's summary, formed once: the reading is linear in the
  // bodies and the laws.
  std::unordered_map<std::string, int> body_of_name, group_of_name;
  for (std::size_t i = 0; i < world.bodies.size(); ++i) body_of_name.emplace(world.bodies[i].name, static_cast<int>(i));
  std::vector<SideSummary> group_summaries;
  for (std::size_t g = 0; g < world.groups.size(); ++g) {
    group_of_name.emplace(world.groups[g].name, static_cast<int>(g));
    group_summaries.push_back(summarize(world, -1, static_cast<int>(g)));
  }
  const SceneNode contacts = root.child("contacts");
  for (const auto& [name, node] : contacts.entries()) {
    node.allow_only({"between", "mu", "friction_direction", "restitution", "features", "mu_ramp",
                     "elastic_slip", "collide"});
    ContactLaw law;
    law.name = name;
    const auto pair = node.child("between").items();
    if (pair.size() != 2) node.fail_at("between", "expected two names, of bodies or groups");
    SideSummary sides[2];
    for (int i = 0; i < 2; ++i) {
      const std::string side = pair[i].as_string();
      int& body = i == 0 ? law.body_a : law.body_b;
      int& group = i == 0 ? law.group_a : law.group_b;
      if (const auto found = body_of_name.find(side); found != body_of_name.end()) {
        body = found->second;
        sides[i] = summarize(world, body, -1);
      } else if (const auto found_group = group_of_name.find(side); found_group != group_of_name.end()) {
        group = found_group->second;
        sides[i] = group_summaries[group];
      } else {
        pair[i].fail("no body or group named '" + side + "'");
      }
    }
    if (law.body_a >= 0 && law.body_a == law.body_b) node.fail_at("between", "a body cannot touch itself");
    // A side that is a group of one body, against itself or its own body, pairs nothing.
    const bool one_against_itself =
        (law.group_a >= 0 && law.group_a == law.group_b && sides[0].count < 2) ||
        (law.group_a >= 0 && law.body_b >= 0 && sides[0].count == 1 && world.bodies[law.body_b].group == law.group_a) ||
        (law.group_b >= 0 && law.body_a >= 0 && sides[1].count == 1 && world.bodies[law.body_a].group == law.group_b);
    if (one_against_itself) node.fail_at("between", "this law pairs no two distinct bodies (a group of one body)");
    law.collides = node.boolean("collide", true);
    if (!law.collides) {  // a filter: its pairs never touch, so nothing else of a law applies
      for (const char* key : {"mu", "friction_direction", "restitution", "features", "mu_ramp", "elastic_slip"})
        if (node.has(key)) node.fail_at(key, "a law whose pairs never collide (collide: false) takes no " + std::string(key));
      world.contact_laws.push_back(law);
      continue;
    }
    if (node.has("mu") && node.child("mu").is_sequence()) {
      law.mu = node.vector("mu", 2, 2).head<2>();
      if (!node.has("friction_direction"))
        node.fail_at("friction_direction", "required with an anisotropic mu [mu1, mu2]: the axis of mu1");
    } else {
      law.mu.setConstant(node.number("mu", 0.0));
    }
    if ((law.mu.array() < 0.0).any()) node.fail_at("mu", "the friction coefficient must be >= 0");
    if (node.has("mu_ramp")) {  // [start, end] (s): mu grows linearly from 0 to its value
      const Eigen::Vector3d ramp = node.vector("mu_ramp", 2, 2);
      if (!(ramp(0) >= 0.0 && ramp(1) > ramp(0))) node.fail_at("mu_ramp", "expected [start, end] with 0 <= start < end");
      law.mu_ramp_start = ramp(0);
      law.mu_ramp_end = ramp(1);
    }
    law.elastic_slip = node.non_negative("elastic_slip", 0.0);
    if (node.has("friction_direction"))
      law.friction_direction = node.vector("friction_direction", world.dimension, world.dimension);
    law.restitution = node.number("restitution", 0.0);
    if (law.restitution < 0.0 || law.restitution > 1.0)
      node.fail_at("restitution", "must lie in [0, 1]");
    // An elastic body touches through its boundary nodes; the other bodies through their shapes.
    for (const SideSummary& side : sides)
      if (side.without_shapes >= 0)
        node.fail_at("between", "body '" + world.bodies[side.without_shapes].name + "'" +
                                    (side.name.starts_with("group") ? " (of " + side.name + ")" : "") +
                                    " has no shapes");
    if (const auto [x, y] = elastic_pair(sides[0], sides[1]); x >= 0)
      node.fail_at("between", "contact between two elastic bodies ('" + world.bodies[x].name + "' and '" +
                                  world.bodies[y].name + "') is not supported yet (node-to-surface contact works "
                                  "against rigid shapes)");
    // Node-to-surface contact projects onto spheres, boxes and halfspaces only (deformable_surface.h).
    for (int k = 0; k < 2; ++k)
      if (!sides[k].elastic.empty() && sides[1 - k].hull_shaped >= 0)
        node.fail_at("between", "elastic body '" + world.bodies[sides[k].elastic[0]].name + "' against body '" +
                                    world.bodies[sides[1 - k].hull_shaped].name +
                                    "', which has a capsule, cylinder, convex or mesh shape: node-to-surface contact "
                                    "takes spheres, boxes and halfspaces; use one of those");
    const bool has_elastic = !sides[0].elastic.empty() || !sides[1].elastic.empty();
    const std::string features = node.string("features", "nodes");
    if (features == "faces") law.features = SurfaceFeatures::faces;
    else if (features == "both") law.features = SurfaceFeatures::both;
    else if (features == "smoothed") law.features = SurfaceFeatures::smoothed;
    else if (features != "nodes")
      node.fail_at("features", "expected nodes, faces, both or smoothed, got '" + features + "'");
    if (features == "smoothed" && world.dimension != 2)
      node.fail_at("features", "smoothed is for plane scenes (dimension 2): a curve along the boundary edges");
    if (!has_elastic && features != "nodes")
      node.fail_at("features", "only meaningful when one of the bodies is elastic");
    world.contact_laws.push_back(law);
  }
  // Laws with the same sides, or two laws of one specificity sharing a pair (contact_law_table.h).
  try {
    ContactLawTable table(world);
  } catch (const ContactLawConflict& conflict) {
    contacts.child(world.contact_laws[conflict.law].name).fail_at("between", conflict.what());
  }
}

}  // namespace csim::scene_parts
