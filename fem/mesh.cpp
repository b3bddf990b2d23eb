// Element-type tables and the outer boundary of a mesh.
//
// The local faces follow Gmsh's numbering so that imported and generated meshes agree:
//   quad4/quad8: edge i runs from corner i to corner i+1 (mod 4); quad8 adds its mid-side node 4+i.
//     With the corners counter-clockwise, (t_y, −t_x) then points out of the element.
//   hexa8: the six faces of Gmsh's hexahedron, each written counter-clockwise seen from outside so
//     that (x1 − x0) × (x3 − x0) points outward (checked on the unit cube in tests/fem/mesh_test.cpp).
#include "fem/mesh.h"

#include <algorithm>
#include <array>
#include <map>
#include <string>

namespace csim {
namespace {

// Local node numbers of each face, ordered for an outward normal (see above).
constexpr std::array<std::array<int, 3>, 4> kQuadEdges = {{{0, 1, 4}, {1, 2, 5}, {2, 3, 6}, {3, 0, 7}}};
constexpr std::array<std::array<int, 4>, 6> kHexaFaces = {{
    {0, 3, 2, 1},  // ζ = −1 (bottom)
    {0, 1, 5, 4},  // η = −1
    {0, 4, 7, 3},  // ξ = −1
    {1, 2, 6, 5},  // ξ = +1
    {2, 3, 7, 6},  // η = +1
    {4, 5, 6, 7},  // ζ = +1 (top)
}};

int faces_per_element(ElementType type) { return type == ElementType::hexa8 ? 6 : 4; }

// The nodes of one local face of element e, in outward order.
std::vector<int> face_nodes(const Mesh& mesh, int e, int local_face) {
  const std::vector<int>& element = mesh.elements[e];
  switch (mesh.element_type) {
    case ElementType::quad4: {
      const auto& edge = kQuadEdges[local_face];
      return {element[edge[0]], element[edge[1]]};
    }
    case ElementType::quad8: {
      const auto& edge = kQuadEdges[local_face];
      return {element[edge[0]], element[edge[1]], element[edge[2]]};
    }
    case ElementType::hexa8: {
      std::vector<int> nodes;
      for (int local : kHexaFaces[local_face]) nodes.push_back(element[local]);
      return nodes;
    }
  }
  throw FemError("face_nodes: unknown element type");
}

// Two elements share a face when they share its corners; mid-side nodes follow from the corners.
std::vector<int> corner_key(ElementType type, std::vector<int> nodes) {
  nodes.resize(type == ElementType::hexa8 ? 4 : 2);
  std::sort(nodes.begin(), nodes.end());
  return nodes;
}

}  // namespace

int nodes_per_element(ElementType type) {
  switch (type) {
    case ElementType::quad4: return 4;
    case ElementType::quad8: return 8;
    case ElementType::hexa8: return 8;
  }
  throw FemError("nodes_per_element: unknown element type");
}

int mesh_dimension(ElementType type) {
  switch (type) {
    case ElementType::quad4: return 2;
    case ElementType::quad8: return 2;
    case ElementType::hexa8: return 3;
  }
  throw FemError("mesh_dimension: unknown element type");
}

const char* to_string(ElementType type) {
  switch (type) {
    case ElementType::quad4: return "quad4";
    case ElementType::quad8: return "quad8";
    case ElementType::hexa8: return "hexa8";
  }
  return "unknown";
}

std::vector<Face> boundary_faces(const Mesh& mesh) {
  const int per_element = nodes_per_element(mesh.element_type);
  const int node_count = static_cast<int>(mesh.nodes.size());
  const int element_count = static_cast<int>(mesh.elements.size());
  for (int e = 0; e < element_count; ++e) {
    const std::vector<int>& element = mesh.elements[e];
    if (static_cast<int>(element.size()) != per_element)
      throw FemError("boundary_faces: element " + std::to_string(e) + " has " + std::to_string(element.size()) +
                     " nodes, a " + to_string(mesh.element_type) + " has " + std::to_string(per_element));
    for (int node : element)
      if (node < 0 || node >= node_count)
        throw FemError("boundary_faces: element " + std::to_string(e) + " refers to node " + std::to_string(node) +
                       " of a mesh of " + std::to_string(node_count) + " nodes");
  }

  // Count how many elements share each face (keyed by its sorted corners; the map keeps this
  // deterministic and is only looked up, never iterated into the result).
  const int faces = faces_per_element(mesh.element_type);
  std::map<std::vector<int>, int> sharing;
  for (int e = 0; e < element_count; ++e)
    for (int f = 0; f < faces; ++f) ++sharing[corner_key(mesh.element_type, face_nodes(mesh, e, f))];

  std::vector<Face> boundary;
  for (int e = 0; e < element_count; ++e)
    for (int f = 0; f < faces; ++f) {
      std::vector<int> nodes = face_nodes(mesh, e, f);
      if (sharing.at(corner_key(mesh.element_type, nodes)) == 1) boundary.push_back(Face{e, f, std::move(nodes)});
    }
  return boundary;
}

std::vector<int> nodes_of(const std::vector<Face>& faces) {
  std::vector<int> nodes;
  for (const Face& face : faces) nodes.insert(nodes.end(), face.nodes.begin(), face.nodes.end());
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

}  // namespace csim
