// Structured meshes. The plane shapes (rectangle, annulus) share one generator: a grid of
// quadrilaterals in a parameter plane (a, b) ∈ [0, 1]², mapped to space by a function of the shape.
// A quad8 grid is the quad4 grid of half the step without its element centres, which gives the
// serendipity nodes and shares each mid-side node between the two elements of its edge.
// The 3D annulus is the quad4 annulus extruded along +z: one copy of the plane nodes per layer.
#include "fem/mesh_generators.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <numeric>
#include <sstream>
#include <string>

namespace csim {
namespace {

// ----- argument checks ------------------------------------------------------------------------------

[[noreturn]] void invalid(const char* function, const char* argument, const std::string& requirement, double value) {
  std::ostringstream message;
  message << function << ": " << argument << " must be " << requirement << " (got " << value << ")";
  throw FemError(message.str());
}

void require_length(const char* function, const char* argument, double value) {
  if (!(std::isfinite(value) && value > 0.0)) invalid(function, argument, "finite and > 0 (m)", value);
}

void require_divisions(const char* function, const char* argument, int value, int minimum) {
  if (value < minimum) invalid(function, argument, ">= " + std::to_string(minimum), value);
}

// Keeps node counts and indices within int, the index type of Mesh.
void require_size(const char* function, const char* divisions, double node_count) {
  if (node_count > static_cast<double>(std::numeric_limits<int>::max() / 8)) {
    std::ostringstream message;
    message << function << ": " << divisions << " give about " << node_count
            << " nodes, too many for int node indices";
    throw FemError(message.str());
  }
}

void require_radii(const char* function, double inner_radius, double outer_radius) {
  require_length(function, "inner_radius", inner_radius);
  require_length(function, "outer_radius", outer_radius);
  if (!(inner_radius < outer_radius)) {
    std::ostringstream message;
    message << function << ": inner_radius must be < outer_radius (got " << inner_radius << " and " << outer_radius
            << ")";
    throw FemError(message.str());
  }
}

void require_plane_type(const char* function, ElementType type) {
  if (type != ElementType::quad4 && type != ElementType::quad8) {
    std::ostringstream message;
    message << function << ": type must be quad4 or quad8 (got " << to_string(type) << ")";
    throw FemError(message.str());
  }
}

void require_placement(const char* function, const Placement& placement, bool plane) {
  if (!std::isfinite(placement.angle)) invalid(function, "placement.angle", "finite (rad)", placement.angle);
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(placement.offset(k))) invalid(function, "placement.offset", "finite (m)", placement.offset(k));
  if (plane && placement.offset.z() != 0.0)
    invalid(function, "placement.offset.z", "0 for a plane mesh (m)", placement.offset.z());
}

// ----- shared steps ---------------------------------------------------------------------------------

void place(Mesh& mesh, const Placement& placement) {
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(placement.angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (Eigen::Vector3d& x : mesh.nodes) x = rotation * x + placement.offset;
}

// The boundary faces whose nodes all belong to node_set (sorted): the faces of one side of the shape.
std::vector<Face> faces_within(const std::vector<Face>& boundary, const std::vector<int>& node_set) {
  std::vector<Face> faces;
  for (const Face& face : boundary) {
    const bool inside = std::all_of(face.nodes.begin(), face.nodes.end(), [&](int node) {
      return std::binary_search(node_set.begin(), node_set.end(), node);
    });
    if (inside) faces.push_back(face);
  }
  return faces;
}

void add_side(Mesh& mesh, const std::vector<Face>& boundary, const std::string& name, std::vector<int> nodes) {
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  mesh.face_sets[name] = faces_within(boundary, nodes);
  mesh.node_sets[name] = std::move(nodes);
}

// ----- plane grid -----------------------------------------------------------------------------------

// Grid points (i, j), i = 0..last_i along a, j = 0..last_j along b (j wraps to 0 past last_j when the
// grid closes on itself along b). quad8 grids use half steps and have no point where i and j are
// both odd (the element centres).
class PlaneGrid {
 public:
  using Position = std::function<Eigen::Vector3d(double a, double b)>;  // a, b ∈ [0, 1] → m

  PlaneGrid(int divisions_a, int divisions_b, bool closed_b, ElementType type, const Position& position)
      : step_(type == ElementType::quad8 ? 2 : 1),
        last_i_(step_ * divisions_a),
        rows_(step_ * divisions_b + (closed_b ? 0 : 1)),
        closed_b_(closed_b),
        index_(static_cast<std::size_t>(last_i_ + 1) * static_cast<std::size_t>(rows_), -1) {
    mesh_.element_type = type;
    for (int j = 0; j < rows_; ++j)
      for (int i = 0; i <= last_i_; ++i) {
        if (step_ == 2 && i % 2 == 1 && j % 2 == 1) continue;
        // Fractions i / last reach exactly 0 and 1 at the ends, so sides keep exact coordinates.
        const double a = static_cast<double>(i) / last_i_;
        const double b = static_cast<double>(j) / (step_ * divisions_b);
        index_[slot(i, j)] = static_cast<int>(mesh_.nodes.size());
        mesh_.nodes.push_back(position(a, b));
      }
    for (int row = 0; row < divisions_b; ++row)
      for (int column = 0; column < divisions_a; ++column) {
        const int i = step_ * column, j = step_ * row, s = step_;
        std::vector<int> element = {node(i, j), node(i + s, j), node(i + s, j + s), node(i, j + s)};
        if (step_ == 2) {
          // mid-side nodes of edges 0-1, 1-2, 2-3, 3-0
          for (int n : {node(i + 1, j), node(i + 2, j + 1), node(i + 1, j + 2), node(i, j + 1)}) element.push_back(n);
        }
        mesh_.elements.push_back(std::move(element));
      }
  }

  int node(int i, int j) const { return index_[slot(i, j)]; }
  int last_i() const { return last_i_; }
  int last_j() const { return rows_ - 1; }  // the last row of an open grid

  // The nodes of all points (i, j) that satisfy the predicate, in node order.
  std::vector<int> nodes_where(const std::function<bool(int i, int j)>& predicate) const {
    std::vector<int> nodes;
    for (int j = 0; j < rows_; ++j)
      for (int i = 0; i <= last_i_; ++i)
        if (node(i, j) >= 0 && predicate(i, j)) nodes.push_back(node(i, j));
    return nodes;
  }

  Mesh& mesh() { return mesh_; }

 private:
  std::size_t slot(int i, int j) const {
    if (closed_b_) j %= rows_;
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(last_i_ + 1) + static_cast<std::size_t>(i);
  }

  int step_;
  int last_i_;
  int rows_;
  bool closed_b_;
  std::vector<int> index_;
  Mesh mesh_;
};

// ----- annulus and extrusion ------------------------------------------------------------------------

// The plane annulus, unplaced, with its sides "inner" and "outer"; arguments already checked.
Mesh plane_annulus(double inner_radius, double outer_radius, int n_circumferential, int n_radial, ElementType type) {
  // a runs outward along the radius and b counter-clockwise around: x_r × x_θ = r e_z, so every
  // element is counter-clockwise with a positive Jacobian.
  const double two_pi = 2.0 * std::numbers::pi;
  PlaneGrid grid(n_radial, n_circumferential, true, type, [&](double a, double b) {
    const double r = a == 1.0 ? outer_radius : inner_radius + (outer_radius - inner_radius) * a;
    const double theta = two_pi * b;
    return Eigen::Vector3d(r * std::cos(theta), r * std::sin(theta), 0.0);
  });
  Mesh& mesh = grid.mesh();
  const int last_i = grid.last_i();
  const std::vector<Face> boundary = boundary_faces(mesh);
  add_side(mesh, boundary, "inner", grid.nodes_where([](int i, int) { return i == 0; }));
  add_side(mesh, boundary, "outer", grid.nodes_where([&](int i, int) { return i == last_i; }));
  return std::move(mesh);
}

// The hexa8 mesh swept by a quad4 mesh of z = 0 through −width/2 ≤ z ≤ width/2 (m) in `layers`
// equal layers: layer k's nodes are the plane nodes, in their order, at z_k; elements layer by layer.
// Each counter-clockwise quad becomes the bottom face of its hexa8 (fem/mesh.h), the top face above
// it, so every Jacobian keeps the sign of the plane one. No node sets: see nodes_above.
Mesh extrude(const Mesh& plane, double width, int layers) {
  Mesh mesh;
  mesh.element_type = ElementType::hexa8;
  const int per_layer = static_cast<int>(plane.nodes.size());
  for (int k = 0; k <= layers; ++k) {
    // width · (k / layers − 1/2) is exactly ∓width/2 at the end faces and 0 in a middle layer.
    const double z = width * (static_cast<double>(k) / layers - 0.5);
    for (const Eigen::Vector3d& x : plane.nodes) mesh.nodes.emplace_back(x.x(), x.y(), z);
  }
  for (int k = 0; k < layers; ++k)
    for (const std::vector<int>& quad : plane.elements) {
      std::vector<int> hexa;
      for (int level : {k, k + 1})
        for (int corner = 0; corner < 4; ++corner) hexa.push_back(quad[corner] + level * per_layer);
      mesh.elements.push_back(std::move(hexa));
    }
  return mesh;
}

// The nodes of an extruded mesh above the plane nodes `plane_nodes`, in layers first..last.
std::vector<int> nodes_above(const std::vector<int>& plane_nodes, int per_layer, int first_layer, int last_layer) {
  std::vector<int> nodes;
  for (int k = first_layer; k <= last_layer; ++k)
    for (int node : plane_nodes) nodes.push_back(node + k * per_layer);
  return nodes;
}

}  // namespace

Mesh rectangle_mesh(double width, double height, int nx, int ny, ElementType type, const Placement& placement) {
  constexpr const char* kFunction = "rectangle_mesh";
  require_length(kFunction, "width", width);
  require_length(kFunction, "height", height);
  require_divisions(kFunction, "nx", nx, 1);
  require_divisions(kFunction, "ny", ny, 1);
  require_plane_type(kFunction, type);
  require_placement(kFunction, placement, true);
  require_size(kFunction, "nx, ny", (2.0 * nx + 1.0) * (2.0 * ny + 1.0));

  PlaneGrid grid(nx, ny, false, type,
                 [&](double a, double b) { return Eigen::Vector3d(width * a, height * b, 0.0); });
  Mesh& mesh = grid.mesh();
  const int last_i = grid.last_i(), last_j = grid.last_j();
  const std::vector<Face> boundary = boundary_faces(mesh);
  add_side(mesh, boundary, "bottom", grid.nodes_where([](int, int j) { return j == 0; }));
  add_side(mesh, boundary, "top", grid.nodes_where([&](int, int j) { return j == last_j; }));
  add_side(mesh, boundary, "left", grid.nodes_where([](int i, int) { return i == 0; }));
  add_side(mesh, boundary, "right", grid.nodes_where([&](int i, int) { return i == last_i; }));
  mesh.node_sets["bottom_left"] = {grid.node(0, 0)};
  mesh.node_sets["bottom_right"] = {grid.node(last_i, 0)};
  mesh.node_sets["top_left"] = {grid.node(0, last_j)};
  mesh.node_sets["top_right"] = {grid.node(last_i, last_j)};
  place(mesh, placement);
  return std::move(mesh);
}

Mesh annulus_mesh(double inner_radius, double outer_radius, int n_circumferential, int n_radial, ElementType type,
                  const Placement& placement) {
  constexpr const char* kFunction = "annulus_mesh";
  require_radii(kFunction, inner_radius, outer_radius);
  // Fewer than 3 elements around would make elements that overlap themselves or have no area.
  require_divisions(kFunction, "n_circumferential", n_circumferential, 3);
  require_divisions(kFunction, "n_radial", n_radial, 1);
  require_plane_type(kFunction, type);
  require_placement(kFunction, placement, true);
  require_size(kFunction, "n_circumferential, n_radial", (2.0 * n_circumferential) * (2.0 * n_radial + 1.0));

  Mesh mesh = plane_annulus(inner_radius, outer_radius, n_circumferential, n_radial, type);
  place(mesh, placement);
  return mesh;
}

Mesh annulus_mesh_3d(double inner_radius, double outer_radius, double width, int n_circumferential, int n_radial,
                     int n_axial, const Placement& placement) {
  constexpr const char* kFunction = "annulus_mesh_3d";
  require_radii(kFunction, inner_radius, outer_radius);
  require_length(kFunction, "width", width);
  require_divisions(kFunction, "n_circumferential", n_circumferential, 3);  // as annulus_mesh
  require_divisions(kFunction, "n_radial", n_radial, 1);
  require_divisions(kFunction, "n_axial", n_axial, 1);
  require_placement(kFunction, placement, false);
  require_size(kFunction, "n_circumferential, n_radial, n_axial",
               static_cast<double>(n_circumferential) * (n_radial + 1.0) * (n_axial + 1.0));

  const Mesh plane = plane_annulus(inner_radius, outer_radius, n_circumferential, n_radial, ElementType::quad4);
  Mesh mesh = extrude(plane, width, n_axial);
  const int per_layer = static_cast<int>(plane.nodes.size());
  std::vector<int> every_plane_node(per_layer);
  std::iota(every_plane_node.begin(), every_plane_node.end(), 0);

  const std::vector<Face> boundary = boundary_faces(mesh);
  add_side(mesh, boundary, "inner", nodes_above(plane.node_sets.at("inner"), per_layer, 0, n_axial));
  add_side(mesh, boundary, "outer", nodes_above(plane.node_sets.at("outer"), per_layer, 0, n_axial));
  add_side(mesh, boundary, "zmin", nodes_above(every_plane_node, per_layer, 0, 0));
  add_side(mesh, boundary, "zmax", nodes_above(every_plane_node, per_layer, n_axial, n_axial));
  mesh.node_sets["all"] = nodes_above(every_plane_node, per_layer, 0, n_axial);
  place(mesh, placement);
  return mesh;
}

Mesh box_mesh(double lx, double ly, double lz, int nx, int ny, int nz, const Placement& placement) {
  constexpr const char* kFunction = "box_mesh";
  require_length(kFunction, "lx", lx);
  require_length(kFunction, "ly", ly);
  require_length(kFunction, "lz", lz);
  require_divisions(kFunction, "nx", nx, 1);
  require_divisions(kFunction, "ny", ny, 1);
  require_divisions(kFunction, "nz", nz, 1);
  require_placement(kFunction, placement, false);
  require_size(kFunction, "nx, ny, nz", (nx + 1.0) * (ny + 1.0) * (nz + 1.0));

  Mesh mesh;
  mesh.element_type = ElementType::hexa8;
  auto node = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        mesh.nodes.emplace_back(lx * (static_cast<double>(i) / nx), ly * (static_cast<double>(j) / ny),
                                lz * (static_cast<double>(k) / nz));
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        mesh.elements.push_back({node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k),
                                 node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1),
                                 node(i, j + 1, k + 1)});

  auto nodes_where = [&](const std::function<bool(int, int, int)>& predicate) {
    std::vector<int> nodes;
    for (int k = 0; k <= nz; ++k)
      for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i)
          if (predicate(i, j, k)) nodes.push_back(node(i, j, k));
    return nodes;
  };
  const std::vector<Face> boundary = boundary_faces(mesh);
  add_side(mesh, boundary, "xmin", nodes_where([](int i, int, int) { return i == 0; }));
  add_side(mesh, boundary, "xmax", nodes_where([&](int i, int, int) { return i == nx; }));
  add_side(mesh, boundary, "ymin", nodes_where([](int, int j, int) { return j == 0; }));
  add_side(mesh, boundary, "ymax", nodes_where([&](int, int j, int) { return j == ny; }));
  add_side(mesh, boundary, "zmin", nodes_where([](int, int, int k) { return k == 0; }));
  add_side(mesh, boundary, "zmax", nodes_where([&](int, int, int k) { return k == nz; }));
  for (int cz = 0; cz <= 1; ++cz)
    for (int cy = 0; cy <= 1; ++cy)
      for (int cx = 0; cx <= 1; ++cx) {
        const std::string name =
            "x" + std::to_string(cx) + "y" + std::to_string(cy) + "z" + std::to_string(cz);
        mesh.node_sets[name] = {node(cx * nx, cy * ny, cz * nz)};
      }
  place(mesh, placement);
  return mesh;
}

}  // namespace csim
