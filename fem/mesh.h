// Finite-element meshes as plain data: nodes, one element type per mesh, named node and face sets.
// fem/ knows nothing of contact, time or the engine: it takes and returns meshes, matrices, vectors.
//
// Conventions (those of Gmsh, so that imported and generated meshes agree):
//   quad4  corners counter-clockwise;
//   quad8  corners counter-clockwise, then the mid-side nodes of edges 0-1, 1-2, 2-3, 3-0;
//   hexa8  bottom face 0-1-2-3 counter-clockwise seen from the top (+ζ), then top face 4-5-6-7 above
//          them (node i+4 above node i).
// Plane meshes (quad4, quad8) live in z = 0 and are plane strain, of unit thickness unless the
// caller says otherwise. Coordinates in metres.
#pragma once

#include <Eigen/Dense>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace csim {

enum class ElementType { quad4, quad8, hexa8 };

int nodes_per_element(ElementType type);   // 4, 8, 8
int mesh_dimension(ElementType type);      // 2, 2, 3
const char* to_string(ElementType type);

// A face of an element on the boundary: an edge in 2D (2 nodes for quad4, 3 for quad8: corner, corner,
// mid-side), a quadrilateral in 3D (4 nodes). Its nodes run so that the outward normal is
//   2D: (t_y, −t_x) for the edge tangent t from the first node to the second;
//   3D: (x1 − x0) × (x3 − x0) for the nodes 0-1-2-3 (counter-clockwise seen from outside).
struct Face {
  int element = -1;
  int local_face = -1;
  std::vector<int> nodes;
};

struct Mesh {
  ElementType element_type = ElementType::quad4;
  std::vector<Eigen::Vector3d> nodes;                     // m; z = 0 for plane meshes
  std::vector<std::vector<int>> elements;                 // node indices, in the order above
  std::map<std::string, std::vector<int>> node_sets;      // sorted, unique node indices
  std::map<std::string, std::vector<Face>> face_sets;

  int dimension() const { return mesh_dimension(element_type); }
  int dofs_per_node() const { return dimension(); }
  int dof_count() const { return dofs_per_node() * static_cast<int>(nodes.size()); }
};

// An error in a mesh or a material, naming the entity (file, element, group, key): thrown by fem/.
struct FemError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The faces of the mesh that belong to one element only (the outer boundary), with their nodes.
std::vector<Face> boundary_faces(const Mesh& mesh);

// The nodes of a list of faces, sorted and unique.
std::vector<int> nodes_of(const std::vector<Face>& faces);

}  // namespace csim
