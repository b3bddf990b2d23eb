// bodies: point masses, rigid bodies and fixed bodies with their collision shapes.
//   type: point | rigid | fixed
//   mass (kg), inertia (2D: kg·m² about the centre of mass; 3D: principal [I1, I2, I3]; default from a
//   single box or sphere shape), position (reference configuration, m), angle (deg, about z, or about
//   `axis` in 3D), initial_displacement (m), velocity (m/s), angular_velocity (rad/s; 3D: body frame)
//   shapes: NAME: {type: box, size: [...]} | {type: sphere, radius} | {type: halfspace, normal, offset}
//           | 3D only: {type: capsule, radius, length} (length: of its cylindrical part, along the
//           shape's z) | {type: cylinder, radius, length} (along z) | {type: convex, vertices:
//           [[x, y, z], ...]} (their hull) | {type: mesh, file: F.obj | F.stl} (fixed bodies; the file
//           beside the scene), each with an optional position and angle in the body frame;
//   prescribed: {COMPONENT: value | [[t, value], ...]}: the component's displacement from the
//           reference position (m, or rad for rz) as a constant or a table interpolated linearly in
//           time (a ground moved along a path, a hub held at its centre; 3D rotations rx, ry, rz: the
//           angle turned about that body axis, exact for turns about one axis), or
//           {value: ..., until: T (s)}: prescribed until T, then free (a hub's spin held during a press).
//   group: NAME: the group of bodies it belongs to (at most one), that contact laws may name as a side
//           (any body type; a name may not be both a body's and a group's).
#include "engine/bodies/fe_body.h"
#include "engine/bodies/fixed_body.h"
#include "engine/bodies/point_mass.h"
#include "engine/bodies/rigid_body_2d.h"
#include "engine/bodies/rigid_body_3d.h"
#include "contact/convex_hull.h"
#include "tools/scene/mesh_file.h"
#include "tools/scene/scene_parts.h"

#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <unordered_map>

namespace csim::scene_parts {

namespace {

constexpr double kDegree = M_PI / 180.0;

Eigen::Matrix3d rotation(const SceneNode& node, int dimension) {
  const double angle = node.has("angle") ? node.number("angle") * kDegree : 0.0;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  if (dimension == 3 && node.has("axis")) {
    axis = node.vector("axis", 3, 3);
    if (axis.norm() == 0.0) node.fail_at("axis", "must not be zero");
    axis.normalize();
  }
  return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

ShapeInstance read_shape(const std::string& name, const SceneNode& node, int dimension) {
  ShapeInstance shape;
  shape.name = name;
  const std::string type = node.string("type");
  if (type == "box") {
    node.allow_only({"type", "size", "position", "angle", "axis"});
    Eigen::Vector3d size = node.vector("size", dimension, dimension);
    if (dimension == 2) size.z() = 1.0;  // plane strain: unit depth
    if ((size.array() <= 0.0).any()) node.fail_at("size", "every size must be > 0");
    shape.shape = Box{0.5 * size};
  } else if (type == "sphere") {
    node.allow_only({"type", "radius", "position", "angle", "axis"});
    shape.shape = Sphere{node.positive("radius")};
  } else if (type == "capsule" || type == "cylinder" || type == "convex" || type == "mesh") {
    if (dimension == 2)
      node.fail_at("type", "a " + type + " is a 3D shape (a plane scene takes box, sphere and halfspace)");
    if (type == "mesh") {
      node.allow_only({"type", "file", "position", "angle", "axis"});
      const std::filesystem::path scene_folder = std::filesystem::path(node.document().file).parent_path();
      try {
        shape.shape = read_mesh_file((scene_folder / node.string("file")).string());
      } catch (const std::runtime_error& e) {
        node.fail_at("file", e.what());
      }
    } else if (type == "convex") {
      node.allow_only({"type", "vertices", "position", "angle", "axis"});
      std::vector<Eigen::Vector3d> points;
      for (const SceneNode& item : node.child("vertices").items()) points.push_back(item.as_vector(3, 3));
      try {
        shape.shape = make_convex(points);
      } catch (const std::invalid_argument& e) {
        node.fail_at("vertices", e.what());
      }
    } else {
      node.allow_only({"type", "radius", "length", "position", "angle", "axis"});
      const double radius = node.positive("radius");
      const double length = type == "capsule" ? node.number("length") : node.positive("length");
      if (!(length >= 0.0)) node.fail_at("length", "must be >= 0 (the length of the capsule's cylindrical part)");
      if (type == "capsule") shape.shape = Capsule{radius, 0.5 * length};
      else shape.shape = Cylinder{radius, 0.5 * length};
    }
  } else if (type == "halfspace") {
    node.allow_only({"type", "normal", "offset", "position", "angle", "axis"});
    Eigen::Vector3d normal = node.vector("normal", dimension, dimension);
    if (normal.norm() == 0.0) node.fail_at("normal", "must not be zero");
    shape.shape = Halfspace{normal.normalized(), node.number("offset", 0.0)};
  } else {
    node.fail_at("type", "unknown shape type '" + type + "' (available: box, sphere, halfspace, capsule, cylinder, convex, mesh)");
  }
  if (node.has("position")) shape.local_pose.translation() = node.vector("position", dimension, dimension);
  shape.local_pose.linear() = rotation(node, dimension);
  return shape;
}

double bounding_radius(const std::vector<ShapeInstance>& shapes) {
  double radius = 0.0;
  for (const ShapeInstance& s : shapes) {
    const double offset = s.local_pose.translation().norm();
    if (const auto* sphere = std::get_if<Sphere>(&s.shape)) radius = std::max(radius, offset + sphere->radius);
    else if (const auto* box = std::get_if<Box>(&s.shape)) radius = std::max(radius, offset + box->half_extents.norm());
    else if (const auto* capsule = std::get_if<Capsule>(&s.shape))
      radius = std::max(radius, offset + capsule->half_length + capsule->radius);
    else if (const auto* cylinder = std::get_if<Cylinder>(&s.shape))
      radius = std::max(radius, offset + std::hypot(cylinder->half_length, cylinder->radius));
    else if (const auto* convex = std::get_if<Convex>(&s.shape))
      for (const Eigen::Vector3d& v : convex->vertices) radius = std::max(radius, offset + v.norm());
    else if (const auto* mesh = std::get_if<TriangleMesh>(&s.shape))
      for (const Eigen::Vector3d& v : mesh->vertices) radius = std::max(radius, offset + v.norm());
    else radius = std::numeric_limits<double>::infinity();
  }
  return radius;
}

// Principal inertia (kg·m², about x, y, z of the shape frame) of a uniform solid capsule: its
// cylinder and two hemispheres, each hemisphere moved from its centroid (3r/8 from its flat face) to
// the capsule's centre by the parallel-axis theorem.
Eigen::Vector3d capsule_inertia(const Capsule& capsule, double mass) {
  const double r = capsule.radius, h = capsule.half_length;
  const double cylinder_volume = M_PI * r * r * 2.0 * h, ball_volume = 4.0 / 3.0 * M_PI * r * r * r;
  const double m_cylinder = mass * cylinder_volume / (cylinder_volume + ball_volume);
  const double m_ball = mass - m_cylinder;
  const double across = m_cylinder * ((2.0 * h) * (2.0 * h) / 12.0 + r * r / 4.0) +
                        m_ball * (0.4 * r * r + h * h + 0.75 * h * r);
  const double along = 0.5 * m_cylinder * r * r + 0.4 * m_ball * r * r;
  return {across, across, along};
}

// Inertia about the centre of mass from a single centred shape: 2D about z, 3D principal. A convex
// hull's centroid must lie at its shape's origin and its principal axes along the shape's axes.
Eigen::Vector3d default_inertia(const SceneNode& node, double mass, const std::vector<ShapeInstance>& shapes,
                                int dimension) {
  if (shapes.size() == 1 && shapes[0].local_pose.translation().isZero()) {
    const Shape& shape = shapes[0].shape;
    // The new shapes' inertia is about their own axes: a turned one needs it given.
    const bool turned = !shapes[0].local_pose.linear().isIdentity();
    if (turned && !std::holds_alternative<Box>(shape) && !std::holds_alternative<Sphere>(shape))
      node.fail_at("inertia", "required: the body's only shape is turned in the body frame (angle), so its "
                              "principal axes are not the body's");
    if (const auto* box = std::get_if<Box>(&shape)) {
      const Eigen::Vector3d s = 2.0 * box->half_extents;
      return mass / 12.0 * Eigen::Vector3d(s.y() * s.y() + s.z() * s.z(), s.x() * s.x() + s.z() * s.z(),
                                           s.x() * s.x() + s.y() * s.y());
    }
    if (const auto* sphere = std::get_if<Sphere>(&shape)) {
      const double r2 = sphere->radius * sphere->radius;
      return Eigen::Vector3d::Constant(dimension == 2 ? 0.5 * mass * r2 : 0.4 * mass * r2);
    }
    if (const auto* capsule = std::get_if<Capsule>(&shape)) return capsule_inertia(*capsule, mass);
    if (const auto* cylinder = std::get_if<Cylinder>(&shape)) {
      const double r2 = cylinder->radius * cylinder->radius, l = 2.0 * cylinder->half_length;
      const double across = mass * (3.0 * r2 + l * l) / 12.0;
      return {across, across, 0.5 * mass * r2};
    }
    if (const auto* convex = std::get_if<Convex>(&shape)) {
      const ConvexMassProperties p = convex_mass_properties(*convex);
      const Eigen::Matrix3d inertia = mass / p.volume * p.inertia_per_density;
      const double size = std::cbrt(p.volume);
      if (p.centroid.norm() > 1e-9 * size)
        node.fail_at("inertia", "required: the convex hull's centroid (" + std::to_string(p.centroid.x()) + ", " +
                                    std::to_string(p.centroid.y()) + ", " + std::to_string(p.centroid.z()) +
                                    ") is not at its shape's origin");
      const Eigen::Matrix3d off_diagonal = inertia - Eigen::Matrix3d(inertia.diagonal().asDiagonal());
      if (off_diagonal.cwiseAbs().maxCoeff() > 1e-9 * inertia.diagonal().maxCoeff())
        node.fail_at("inertia", "required: the convex hull's principal axes are not its shape's axes");
      return inertia.diagonal();
    }
  }
  node.fail_at("inertia", "required (it has no default unless the body has one shape at its origin, "
                          "other than a halfspace)");
}

// One body, its position moved by `offset` (m: a copy's place in its grid, copies_of).
void read_body(const std::string& name, const SceneNode& node, World& world,
               const Eigen::Vector3d& offset = Eigen::Vector3d::Zero()) {
  node.allow_only({"type", "mass", "inertia", "position", "angle", "axis", "initial_displacement", "velocity",
                   "angular_velocity", "shapes", "prescribed", "group", "copies"});
  const int d = world.dimension;
  BodyInstance b;
  b.name = name;
  if (node.has("shapes"))
    for (const auto& [shape_name, shape_node] : node.child("shapes").entries())
      b.shapes.push_back(read_shape(shape_name, shape_node, d));

  const std::string type = node.string("type");
  const Eigen::Vector3d position =
      (node.has("position") ? node.vector("position", d, d) : Eigen::Vector3d::Zero()) + offset;
  const Eigen::Matrix3d orientation = rotation(node, d);
  if (type == "fixed") {
    for (const char* key : {"mass", "inertia", "initial_displacement", "velocity", "angular_velocity"})
      if (node.has(key)) node.fail_at(key, "a fixed body takes no mass or motion");
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = position;
    pose.linear() = orientation;
    b.body = std::make_unique<FixedBody>(pose);
  } else if (type == "point" || type == "rigid") {
    const double mass = node.positive("mass");
    if (type == "point") {
      if (node.has("inertia") || node.has("angle") || node.has("angular_velocity"))
        node.fail("a point mass has no inertia, angle or angular velocity");
      b.body = std::make_unique<PointMass>(d, mass);
    } else if (d == 2) {
      const double inertia = node.has("inertia") ? node.positive("inertia")
                                                 : default_inertia(node, mass, b.shapes, d).z();
      b.body = std::make_unique<RigidBody2d>(mass, inertia);
    } else {
      const Eigen::Vector3d inertia = node.has("inertia") ? node.vector("inertia", 3, 3)
                                                          : default_inertia(node, mass, b.shapes, d);
      if ((inertia.array() <= 0.0).any()) node.fail_at("inertia", "every principal inertia must be > 0");
      b.body = std::make_unique<RigidBody3d>(mass, inertia);
    }
  } else {
    node.fail_at("type", "unknown body type '" + type + "' (available: point, rigid, fixed, elastic)");
  }
  b.body->bounding_radius = bounding_radius(b.shapes);
  if (!b.body->fixed() && !std::isfinite(b.body->bounding_radius))
    node.fail("a halfspace can only belong to a fixed body");
  if (!b.body->fixed() && node.has("shapes"))
    for (const auto& [shape_name, shape_node] : node.child("shapes").entries())
      if (shape_node.string("type") == "mesh")
        shape_node.fail_at("type", "a mesh can only belong to a fixed body (a terrain): mesh–mesh contact is not "
                                   "computed; give a moving body a convex shape");

  // Reference configuration, then the initial state.
  const int nq = b.body->position_size(), nv = b.body->velocity_size();
  b.reference_position.setZero(nq);
  b.initial_velocity.setZero(nv);
  if (nq > 0) {
    b.reference_position.head(d) = position.head(d);
    if (type == "rigid" && d == 2) {
      b.reference_position(2) = node.has("angle") ? node.number("angle") * kDegree : 0.0;
    } else if (type == "rigid") {
      const Eigen::Quaterniond q(orientation);
      b.reference_position.tail<4>() << q.w(), q.x(), q.y(), q.z();
    }
    b.initial_position = b.reference_position;
    if (node.has("initial_displacement"))
      b.initial_position.head(d) += node.vector("initial_displacement", d, d).head(d);
    if (node.has("velocity")) b.initial_velocity.head(d) = node.vector("velocity", d, d).head(d);
    if (node.has("angular_velocity")) {
      if (type != "rigid") node.fail_at("angular_velocity", "only rigid bodies rotate");
      if (d == 2) b.initial_velocity(2) = node.number("angular_velocity");
      else b.initial_velocity.tail<3>() = node.vector("angular_velocity", 3, 3);
    }
  }
  if (node.has("prescribed")) {
    if (type == "fixed") node.fail_at("prescribed", "a fixed body does not move");
    for (const auto& [component, value] : node.child("prescribed").entries()) {
      PrescribedComponent p;
      p.body = static_cast<int>(world.bodies.size());
      p.component = b.body->velocity_index(component);
      if (p.component < 0)
        value.fail("body '" + name + "' has no prescribable component '" + component + "'");
      if (value.is_map()) {  // {value: V | [[t, V], ...], until: T}
        value.allow_only({"value", "until"});
        p.until = value.number("until");
      }
      const SceneNode values = value.is_map() ? value.child("value") : value;
      if (values.is_sequence()) {
        read_table_rows(values, p.value.table);
        if (p.value.table.empty()) values.fail("the table must not be empty");
      } else {
        p.value.table.emplace_back(0.0, values.as_number());
      }
      world.prescribed.push_back(p);
    }
  }
  world.bodies.push_back(std::move(b));
}

// A body's `copies: {grid: [nx, ny(, nz)], spacing: [dx, dy(, dz)]}`: nx · ny · nz bodies, the copy
// (i, j, k) at position + (i dx, j dy, k dz), named NAME_n with n = (i ny + j) nz + k (x slowest), and
// in the group NAME unless the body names its own. Returns each copy's name and offset (m).
std::vector<std::pair<std::string, Eigen::Vector3d>> copies_of(const std::string& name, const SceneNode& node,
                                                               int dimension) {
  const SceneNode copies = node.child("copies");
  copies.expect_map();
  copies.allow_only({"grid", "spacing"});
  const std::vector<SceneNode> grid = copies.child("grid").items();
  if (static_cast<int>(grid.size()) != dimension)
    copies.fail_at("grid", "expected " + std::to_string(dimension) + " counts, one per axis");
  long count[3] = {1, 1, 1};
  long total = 1;
  for (int a = 0; a < dimension; ++a) {
    const double n = grid[a].as_number();
    if (!(n >= 1.0 && n <= 1e6 && n == std::floor(n))) copies.fail_at("grid", "each count must be a whole number >= 1");
    count[a] = static_cast<long>(n);
    total *= count[a];
  }
  if (total > 1000000) copies.fail_at("grid", "at most 1 000 000 copies");
  const Eigen::Vector3d spacing = copies.vector("spacing", dimension, dimension);
  std::vector<std::pair<std::string, Eigen::Vector3d>> out;
  out.reserve(static_cast<std::size_t>(total));
  for (long i = 0; i < count[0]; ++i)
    for (long j = 0; j < count[1]; ++j)
      for (long k = 0; k < count[2]; ++k)
        out.emplace_back(name + "_" + std::to_string(out.size()),
                         Eigen::Vector3d(i * spacing.x(), j * spacing.y(), k * spacing.z()));
  return out;
}

}  // namespace

void read_bodies(const SceneNode& root, World& world) {
  const auto entries = root.child("bodies").entries();
  std::unordered_map<std::string, int> group_index;
  std::vector<int> entry_of_body;  // the entry that declared each body (copies: one entry, many bodies)
  const auto join_group = [&](const SceneNode& node, const std::string& group) {
    if (group.empty()) node.fail_at("group", "a group's name must not be empty");
    const auto [at, added] = group_index.emplace(group, static_cast<int>(world.groups.size()));
    if (added) world.groups.push_back({group, {}});
    world.bodies.back().group = at->second;
    world.groups[at->second].bodies.push_back(static_cast<int>(world.bodies.size()) - 1);
  };
  std::unordered_map<std::string, int> declared;  // names of the entries, for the copies' names
  for (std::size_t e = 0; e < entries.size(); ++e) declared.emplace(entries[e].first, static_cast<int>(e));
  for (std::size_t e = 0; e < entries.size(); ++e) {
    const auto& [name, node] = entries[e];
    node.expect_map();
    const bool elastic = node.has("type") && node.string("type") == "elastic";
    if (node.has("copies")) {
      if (elastic) node.fail_at("copies", "copies are for point, rigid and fixed bodies");
      const std::string group = node.has("group") ? node.string("group") : name;
      for (const auto& [copy, offset] : copies_of(name, node, world.dimension)) {
        if (declared.count(copy))
          node.fail_at("copies", "the copy '" + copy + "' has the name of another body; rename one of them");
        read_body(copy, node, world, offset);
        entry_of_body.push_back(static_cast<int>(e));
        join_group(node, group);
      }
      continue;
    }
    if (elastic) read_elastic_body(name, node, world);
    else read_body(name, node, world);
    entry_of_body.push_back(static_cast<int>(e));
    if (node.has("group")) join_group(node, node.string("group"));
  }
  if (world.bodies.empty()) root.fail_at("bodies", "a scene needs at least one body");
  // A between names a body or a group: one name cannot be both.
  for (std::size_t i = 0; i < world.bodies.size(); ++i) {
    const auto clash = group_index.find(world.bodies[i].name);
    if (clash == group_index.end()) continue;
    const int member = entry_of_body[world.groups[clash->second].bodies.front()];
    entries[member].second.fail_at(entries[member].second.has("group") ? "group" : "copies", "'" + clash->first + "' is also the name of a body: a contact law's "
                                            "between could not tell them apart; rename the group or the body");
  }
  world.finalize_layout();
  read_ties(root, world);
}

int contact_law_named(const SceneNode& node, const std::string& key, const World& world) {
  const std::string name = node.string(key);
  for (std::size_t i = 0; i < world.contact_laws.size(); ++i)
    if (world.contact_laws[i].name == name) return static_cast<int>(i);
  node.fail_at(key, "no contact law named '" + name + "'");
}

Eigen::Vector3d node_point(const SceneNode& node, const BodyInstance& body) {
  const FeBody* fe = body.body->finite_elements();
  if (!fe) node.fail_at("node", "node sets belong to elastic bodies");
  const std::string set = node.string("node");
  const auto it = fe->mesh().node_sets.find(set);
  if (it == fe->mesh().node_sets.end() || it->second.size() != 1)
    node.fail_at("node", "the mesh of '" + body.name + "' has no one-node set '" + set + "'");
  return fe->mesh().nodes[it->second.front()];
}

int body_named(const SceneNode& node, const std::string& key, const World& world) {
  const std::string name = node.string(key);
  const int index = world.body_index(name);
  if (index < 0) node.fail_at(key, "no body named '" + name + "'");
  return index;
}

}  // namespace csim::scene_parts
