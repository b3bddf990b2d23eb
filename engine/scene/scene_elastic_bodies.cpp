// bodies of type elastic: a finite-element body (fem/) built from a mesh generator or a Gmsh file.
//   mesh: {generator: rectangle, size: [w, h], divisions: [nx, ny], element: quad4 | quad8}
//       | {generator: box, size: [lx, ly, lz], divisions: [nx, ny, nz]}                (hexa8)
//       | {generator: annulus, inner_radius, outer_radius, divisions: [n_around, n_radial], element}
//       | {file: NAME.msh}  (Gmsh MSH 4.1 ASCII, beside the scene file)
//     with an optional position (m) and angle (deg) for the generators;
//   material: {young (Pa), poisson, density (kg/m³)}; thickness (m, plane strain, default 1);
//   mass: consistent | lumped; fixed: {SET: [x, y(, z)]}: the components held at zero on a node set
//   (or face set) of the mesh; velocity: a uniform initial velocity (m/s).
#include "engine/bodies/fe_body.h"
#include "engine/scene/scene_parts.h"
#include "fem/gmsh_reader.h"
#include "fem/mesh_generators.h"

#include <cmath>
#include <filesystem>

namespace csim::scene_parts {

namespace {

int whole(const SceneNode& node, double value, const std::string& what) {
  if (value < 1 || value != std::floor(value)) node.fail(what + " must be whole numbers >= 1");
  return static_cast<int>(value);
}

ElementType element_type(const SceneNode& node, const std::string& default_type) {
  const std::string name = node.string("element", default_type);
  if (name == "quad4") return ElementType::quad4;
  if (name == "quad8") return ElementType::quad8;
  if (name == "hexa8") return ElementType::hexa8;
  node.fail_at("element", "unknown element '" + name + "' (available: quad4, quad8, hexa8)");
}

Mesh read_mesh(const SceneNode& node, int dimension) {
  node.allow_only({"generator", "file", "size", "divisions", "element", "inner_radius", "outer_radius", "position",
                   "angle"});
  try {
    if (node.has("file")) {
      if (node.has("generator")) node.fail("give either file or generator, not both");
      const std::filesystem::path scene_folder = std::filesystem::path(node.document().file).parent_path();
      return read_gmsh((scene_folder / node.string("file")).string());
    }
    Placement placement;
    if (node.has("position")) placement.offset = node.vector("position", dimension, dimension);
    placement.angle = node.number("angle", 0.0) * M_PI / 180.0;
    const std::string generator = node.string("generator");
    if (generator == "rectangle") {
      const Eigen::Vector3d size = node.vector("size", 2, 2), divisions = node.vector("divisions", 2, 2);
      return rectangle_mesh(size.x(), size.y(), whole(node.child("divisions"), divisions.x(), "divisions"),
                            whole(node.child("divisions"), divisions.y(), "divisions"), element_type(node, "quad4"),
                            placement);
    }
    if (generator == "box") {
      const Eigen::Vector3d size = node.vector("size", 3, 3), n = node.vector("divisions", 3, 3);
      const SceneNode divisions = node.child("divisions");
      return box_mesh(size.x(), size.y(), size.z(), whole(divisions, n.x(), "divisions"),
                      whole(divisions, n.y(), "divisions"), whole(divisions, n.z(), "divisions"), placement);
    }
    if (generator == "annulus") {
      const Eigen::Vector3d n = node.vector("divisions", 2, 2);
      const SceneNode divisions = node.child("divisions");
      return annulus_mesh(node.positive("inner_radius"), node.positive("outer_radius"),
                          whole(divisions, n.x(), "divisions"), whole(divisions, n.y(), "divisions"),
                          element_type(node, "quad4"), placement);
    }
    node.fail_at("generator", "unknown mesh generator '" + generator + "' (available: rectangle, box, annulus)");
  } catch (const FemError& e) {
    node.fail(e.what());
  }
}

}  // namespace

void read_elastic_body(const std::string& name, const SceneNode& node, World& world) {
  node.allow_only({"type", "mesh", "material", "thickness", "mass", "fixed", "velocity", "damping"});
  Mesh mesh = read_mesh(node.child("mesh"), world.dimension);
  if (mesh.dimension() != world.dimension)
    node.fail_at("mesh", "a " + std::string(to_string(mesh.element_type)) + " mesh in a " +
                             std::to_string(world.dimension) + "D scene");
  const SceneNode material_node = node.child("material");
  material_node.allow_only({"young", "poisson", "density"});
  ElasticMaterial material;
  material.young = material_node.number("young");
  material.poisson = material_node.number("poisson", 0.0);
  material.density = material_node.number("density");
  const double thickness = node.has("thickness") ? node.positive("thickness") : 1.0;
  const std::string mass = node.string("mass", "consistent");
  if (mass != "consistent" && mass != "lumped") node.fail_at("mass", "expected consistent or lumped");

  // Rayleigh damping {alpha: 1/s, beta: s}: C = alpha M + beta K.
  double alpha = 0.0, beta = 0.0;
  if (node.has("damping")) {
    const SceneNode damping = node.child("damping");
    damping.allow_only({"alpha", "beta"});
    alpha = damping.non_negative("alpha", 0.0);
    beta = damping.non_negative("beta", 0.0);
  }

  std::vector<std::pair<int, int>> fixed;
  if (node.has("fixed")) {
    for (const auto& [set, components] : node.child("fixed").entries()) {
      std::vector<int> nodes;
      if (mesh.node_sets.count(set)) nodes = mesh.node_sets.at(set);
      else if (mesh.face_sets.count(set)) nodes = nodes_of(mesh.face_sets.at(set));
      else components.fail("the mesh has no node or face set '" + set + "'");
      for (const SceneNode& component : components.items()) {
        const std::string axis = component.as_string();
        const int c = axis == "x" ? 0 : axis == "y" ? 1 : axis == "z" && world.dimension == 3 ? 2 : -1;
        if (c < 0) component.fail("expected x, y" + std::string(world.dimension == 3 ? " or z" : ""));
        for (int n : nodes) fixed.emplace_back(n, c);
      }
    }
  }

  BodyInstance b;
  b.name = name;
  try {
    b.body = std::make_unique<FeBody>(std::move(mesh), material, thickness, mass == "lumped", fixed, alpha, beta);
  } catch (const FemError& e) {
    node.fail(e.what());
  }
  const FeBody& body = static_cast<const FeBody&>(*b.body);
  const int n = body.velocity_size();
  b.reference_position.setZero(n);
  b.initial_position.setZero(n);
  b.initial_velocity.setZero(n);
  if (node.has("velocity")) {
    const Eigen::Vector3d velocity = node.vector("velocity", world.dimension, world.dimension);
    for (int i = 0; i < static_cast<int>(body.mesh().nodes.size()); ++i)
      for (int c = 0; c < body.dofs_per_node(); ++c)
        if (body.free_index(i, c) >= 0) b.initial_velocity(body.free_index(i, c)) = velocity(c);
  }
  world.bodies.push_back(std::move(b));
}

}  // namespace csim::scene_parts
