// Gmsh MSH 4.1 ASCII import, in two passes: read the sections from the token stream (msh_tokens.h) into
// plain records (keeping the line of every node and element for the messages), then build the Mesh, its
// node sets and face sets.
#include "fem/gmsh_reader.h"

#include "fem/msh_tokens.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace csim {
namespace {

// ----- records of the file --------------------------------------------------------------------------

struct ElementKind {
  int gmsh_type;
  int dimension;
  int node_count;
  std::optional<ElementType> mesh_type;  // set for the types that can be mesh elements
  const char* name;
};

constexpr ElementKind kElementKinds[] = {
    {15, 0, 1, std::nullopt, "point"},
    {1, 1, 2, std::nullopt, "2-node line"},
    {8, 1, 3, std::nullopt, "3-node line"},
    {3, 2, 4, ElementType::quad4, "4-node quadrangle"},
    {16, 2, 8, ElementType::quad8, "8-node quadrangle"},
    {5, 3, 8, ElementType::hexa8, "8-node hexahedron"},
};

const ElementKind* find_kind(int gmsh_type) {
  for (const ElementKind& kind : kElementKinds)
    if (kind.gmsh_type == gmsh_type) return &kind;
  return nullptr;
}

using EntityKey = std::pair<int, int>;  // (dimension, tag), of an entity or of a physical group

struct RawNode {
  long long tag;
  Eigen::Vector3d x;  // m
  int line;
};

// An element of the file; its node tags are MshContent::node_tags[first_node, first_node + kind->node_count)
// (one array for all the elements: a vector per element would cost an allocation each).
struct RawElement {
  long long tag;
  const ElementKind* kind;
  EntityKey entity;
  std::size_t first_node;
  int line;
};

struct MshContent {
  std::map<EntityKey, std::string> physical_names;
  std::map<EntityKey, std::vector<int>> entity_physicals;  // physical tags of each entity
  std::vector<RawNode> nodes;
  std::vector<RawElement> elements;
  std::vector<long long> node_tags;  // the elements' node tags, element after element

  std::span<const long long> tags_of(const RawElement& element) const {
    return {node_tags.data() + element.first_node, static_cast<std::size_t>(element.kind->node_count)};
  }
};

std::string node_list(std::span<const long long> tags) {
  std::string text;
  for (long long tag : tags) text += (text.empty() ? "" : " ") + std::to_string(tag);
  return text;
}

// ----- sections -------------------------------------------------------------------------------------

void read_mesh_format(MshTokens& in) {
  const std::string version = in.word("the MSH version");
  if (version != "4.1")
    in.fail("MSH version " + in.token_excerpt() + ": only MSH 4.1 ASCII is supported (gmsh -format msh41)");
  const std::string file_type = in.word("the MSH file type");
  if (file_type != "0")
    in.fail("binary MSH (file type " + in.token_excerpt() + "): only MSH 4.1 ASCII is supported");
  in.integer("the MSH data size", 1, std::numeric_limits<int>::max());
  in.expect("$EndMeshFormat");
}

void read_physical_names(MshTokens& in, MshContent& content) {
  const int count = in.count("the number of physical names");
  for (int i = 0; i < count; ++i) {
    const int dimension = in.dimension("a physical group dimension");
    const int tag = in.int_value("a physical tag");
    content.physical_names[{dimension, tag}] = in.quoted("physical name");
  }
  in.expect("$EndPhysicalNames");
}

void read_entities(MshTokens& in, MshContent& content) {
  int counts[4];
  for (int& count : counts) count = in.count("the number of entities of one dimension");
  for (int dimension = 0; dimension < 4; ++dimension)
    for (int i = 0; i < counts[dimension]; ++i) {
      const int tag = in.int_value("an entity tag");
      const int coordinates = dimension == 0 ? 3 : 6;  // a point, or the bounding box of a curve, ...
      for (int k = 0; k < coordinates; ++k) in.real("entity coordinates");
      std::vector<int>& physicals = content.entity_physicals[{dimension, tag}];
      const int physical_count = in.count("the number of physical tags of an entity");
      for (int k = 0; k < physical_count; ++k) physicals.push_back(in.int_value("a physical tag"));
      if (dimension > 0) {
        const int bounding = in.count("the number of bounding entities");
        for (int k = 0; k < bounding; ++k) in.int_value("a bounding entity tag");
      }
    }
  in.expect("$EndEntities");
}

void read_nodes(MshTokens& in, MshContent& content) {
  const int blocks = in.count("the number of node blocks");
  const int total = in.count("the number of nodes");
  in.tag_bound("the smallest node tag");
  in.tag_bound("the largest node tag");
  // Room for the nodes announced, as many as the file can hold (8 bytes each at least: "1\n0 0 0\n").
  content.nodes.reserve(content.nodes.size() + std::min<std::size_t>(total, in.file_size() / 8));
  for (int block = 0; block < blocks; ++block) {
    const int entity_dimension = in.dimension("the entity dimension of a node block");
    in.int_value("the entity tag of a node block");
    const long long parametric = in.integer("the parametric flag of a node block", 0, 1);
    const int in_block = in.count("the number of nodes in a block");
    const std::size_t first = content.nodes.size();
    for (int i = 0; i < in_block; ++i) {
      const int line = in.token_line();
      content.nodes.push_back(RawNode{in.tag("a node tag"), Eigen::Vector3d::Zero(), line});
    }
    // Parametric nodes carry their parametric coordinates (u, v, w up to the entity dimension).
    const int extra = parametric != 0 ? entity_dimension : 0;
    for (int i = 0; i < in_block; ++i) {
      Eigen::Vector3d& x = content.nodes[first + static_cast<std::size_t>(i)].x;
      for (int k = 0; k < 3; ++k) x(k) = in.real("node coordinates");
      for (int k = 0; k < extra; ++k) in.real("parametric node coordinates");
    }
  }
  if (content.nodes.size() != static_cast<std::size_t>(total))
    in.fail("$Nodes announces " + std::to_string(total) + " nodes, its blocks hold " +
            std::to_string(content.nodes.size()));
  in.expect("$EndNodes");
}

void read_elements(MshTokens& in, MshContent& content) {
  const int blocks = in.count("the number of element blocks");
  const int total = in.count("the number of elements");
  in.tag_bound("the smallest element tag");
  in.tag_bound("the largest element tag");
  const std::size_t first = content.elements.size();
  content.elements.reserve(first + std::min<std::size_t>(total, in.file_size() / 4));  // "1 1\n" at least
  std::vector<long long> sorted;  // an element's node tags, sorted (one buffer for all)
  for (int block = 0; block < blocks; ++block) {
    const int entity_dimension = in.dimension("the entity dimension of an element block");
    const int entity_tag = in.int_value("the entity tag of an element block");
    const int gmsh_type = in.int_value("the element type of an element block");
    const ElementKind* kind = find_kind(gmsh_type);
    if (kind == nullptr)
      in.fail("element type " + std::to_string(gmsh_type) +
              " is not supported (supported: 15 point, 1 and 8 lines, 3 and 16 quadrangles, 5 hexahedron)");
    if (kind->dimension != entity_dimension)
      in.fail(std::string("a block of ") + kind->name + " elements on an entity of dimension " +
              std::to_string(entity_dimension));
    const int in_block = in.count("the number of elements in a block");
    // Gmsh writes a block per entity, the mesh's in one or a few large ones: room for the block at once.
    // (As many as the file can hold: 2 bytes a node tag at least.)
    const std::size_t needed =
        content.node_tags.size() + std::min<std::size_t>(static_cast<std::size_t>(in_block) * kind->node_count,
                                                         in.file_size() / 2);
    if (needed > content.node_tags.capacity())
      content.node_tags.reserve(std::max(needed, 2 * content.node_tags.capacity()));
    for (int i = 0; i < in_block; ++i) {
      RawElement element{0, kind, {entity_dimension, entity_tag}, content.node_tags.size(), in.token_line()};
      element.tag = in.tag("an element tag");
      for (int k = 0; k < kind->node_count; ++k) content.node_tags.push_back(in.tag("an element node tag"));
      // A repeated node collapses the element (a quadrangle 1 2 2 3 is a triangle) and its collapsed
      // edge or face matches no neighbour's: a hole in the mesh, which the Jacobians need not show.
      const std::span<const long long> tags = content.tags_of(element);
      sorted.assign(tags.begin(), tags.end());
      std::sort(sorted.begin(), sorted.end());
      if (const auto twice = std::adjacent_find(sorted.begin(), sorted.end()); twice != sorted.end())
        in.fail_at(element.line, "element " + std::to_string(element.tag) + " (" + kind->name + ", nodes " +
                                     node_list(tags) + ") lists node " + std::to_string(*twice) +
                                     " twice: a degenerate element leaves a hole in the mesh");
      content.elements.push_back(element);
    }
  }
  if (content.elements.size() - first != static_cast<std::size_t>(total))
    in.fail("$Elements announces " + std::to_string(total) + " elements, its blocks hold " +
            std::to_string(content.elements.size() - first));
  in.expect("$EndElements");
}

MshContent read_sections(MshTokens& in) {
  MshContent content;
  std::set<std::string> seen;
  while (!in.at_end()) {
    const std::string section = in.word("a section");
    if (section.empty() || section[0] != '$' || in.token_length() > section.size())
      in.fail("expected a section such as $Nodes, found '" + in.token_excerpt() + "'");
    if (seen.empty() && section != "$MeshFormat") in.fail("the file must begin with $MeshFormat");
    if (!seen.insert(section).second) in.fail("section " + section + " appears twice");
    if (section == "$MeshFormat") read_mesh_format(in);
    else if (section == "$PhysicalNames") read_physical_names(in, content);
    else if (section == "$Entities") read_entities(in, content);
    else if (section == "$Nodes") read_nodes(in, content);
    else if (section == "$Elements") read_elements(in, content);
    else if (section == "$PartitionedEntities") in.fail("partitioned meshes are not supported");
    else in.skip_section(section);
  }
  if (seen.empty()) throw FemError(in.path() + ": empty file, not a Gmsh mesh");
  for (const char* required : {"$Entities", "$Nodes", "$Elements"})
    if (seen.count(required) == 0) throw FemError(in.path() + ": missing section " + required);
  return content;
}

// ----- the mesh -------------------------------------------------------------------------------------

std::string group_name(const MshContent& content, const EntityKey& group) {
  const auto found = content.physical_names.find(group);
  return found != content.physical_names.end() ? found->second : "physical_" + std::to_string(group.second);
}

// Node tags of the file -> mesh node indices (file order, nodes of the mesh elements only).
struct NodeNumbering {
  std::vector<std::pair<long long, int>> by_tag;  // (node tag, position in $Nodes), sorted: lookup only
  std::vector<int> index;                         // position -> mesh node, −1 outside the mesh elements

  // The position in $Nodes of a node tag, −1 when no node has it.
  int position(long long tag) const {
    const auto found = std::lower_bound(by_tag.begin(), by_tag.end(), std::make_pair(tag, 0));
    return found != by_tag.end() && found->first == tag ? found->second : -1;
  }
  int mesh_node(long long tag) const { return index[static_cast<std::size_t>(position(tag))]; }
};

// The elements of the highest dimension, of one type, and their nodes.
Mesh mesh_elements(const MshTokens& in, const MshContent& content, NodeNumbering& numbering) {
  int dimension = -1;
  for (const RawElement& element : content.elements) dimension = std::max(dimension, element.kind->dimension);
  if (dimension < 2)
    throw FemError(in.path() + ": no quadrangle or hexahedron elements (Gmsh saves only the elements of physical "
                               "groups when there are any: add a physical surface or volume)");

  numbering.by_tag.reserve(content.nodes.size());
  for (std::size_t i = 0; i < content.nodes.size(); ++i) numbering.by_tag.emplace_back(content.nodes[i].tag, static_cast<int>(i));
  std::sort(numbering.by_tag.begin(), numbering.by_tag.end());
  // A tag given twice: named at its second appearance, the first such in file order.
  int repeated = -1;
  for (std::size_t k = 1; k < numbering.by_tag.size(); ++k)
    if (numbering.by_tag[k].first == numbering.by_tag[k - 1].first && (repeated < 0 || numbering.by_tag[k].second < repeated))
      repeated = numbering.by_tag[k].second;
  if (repeated >= 0) {
    const RawNode& node = content.nodes[static_cast<std::size_t>(repeated)];
    in.fail_at(node.line, "node tag " + std::to_string(node.tag) + " appears twice");
  }
  for (const RawElement& element : content.elements)
    for (long long tag : content.tags_of(element))
      if (numbering.position(tag) < 0)
        in.fail_at(element.line,
                   "element " + std::to_string(element.tag) + " refers to unknown node tag " + std::to_string(tag));

  Mesh mesh;
  const RawElement* first = nullptr;
  std::vector<bool> used(content.nodes.size(), false);
  for (const RawElement& element : content.elements) {
    if (element.kind->dimension != dimension) continue;
    if (first == nullptr) {
      first = &element;
      mesh.element_type = *element.kind->mesh_type;
    } else if (element.kind != first->kind) {
      in.fail_at(element.line, "element " + std::to_string(element.tag) + " is a " + element.kind->name +
                                   " but element " + std::to_string(first->tag) + " (line " +
                                   std::to_string(first->line) + ") is a " + first->kind->name +
                                   ": one element type per mesh");
    }
    for (long long tag : content.tags_of(element)) used[static_cast<std::size_t>(numbering.position(tag))] = true;
  }
  numbering.index.assign(content.nodes.size(), -1);
  mesh.nodes.reserve(static_cast<std::size_t>(std::count(used.begin(), used.end(), true)));
  for (std::size_t i = 0; i < content.nodes.size(); ++i)
    if (used[i]) {
      numbering.index[i] = static_cast<int>(mesh.nodes.size());
      mesh.nodes.push_back(content.nodes[i].x);
    }
  mesh.elements.reserve(static_cast<std::size_t>(std::count_if(
      content.elements.begin(), content.elements.end(), [&](const RawElement& e) { return e.kind->dimension == dimension; })));
  for (const RawElement& element : content.elements) {
    if (element.kind->dimension != dimension) continue;
    std::vector<int> nodes;
    nodes.reserve(static_cast<std::size_t>(element.kind->node_count));
    for (long long tag : content.tags_of(element)) nodes.push_back(numbering.mesh_node(tag));
    mesh.elements.push_back(std::move(nodes));
  }
  return mesh;
}

// Plane meshes live in z = 0 (fem/mesh.h); round-off relative to the size of the mesh is set to 0.
void flatten_plane_mesh(const MshTokens& in, const MshContent& content, const NodeNumbering& numbering, Mesh& mesh) {
  if (mesh.dimension() != 2) return;
  double extent = 0.0;
  for (const Eigen::Vector3d& x : mesh.nodes) extent = std::max({extent, std::abs(x.x()), std::abs(x.y())});
  for (std::size_t i = 0; i < content.nodes.size(); ++i) {
    if (numbering.index[i] < 0) continue;
    Eigen::Vector3d& x = mesh.nodes[static_cast<std::size_t>(numbering.index[i])];
    if (std::abs(x.z()) > 1e-10 * std::max(extent, 1e-300))
      in.fail_at(content.nodes[i].line, "node " + std::to_string(content.nodes[i].tag) + " has z = " +
                                            std::to_string(x.z()) + " m: a plane mesh must lie in z = 0");
    x.z() = 0.0;
  }
}

// The boundary faces of a face group, in element then local-face order; each group element must be one.
std::vector<Face> match_boundary_faces(const MshTokens& in, const MshContent& content, const std::string& name,
                                       int group_dimension,
                                       const std::vector<const RawElement*>& elements,
                                       const NodeNumbering& numbering, const Mesh& mesh,
                                       const std::vector<Face>& boundary) {
  const std::size_t corners = mesh.dimension() == 3 ? 4 : 2;
  auto corner_key = [&](std::vector<int> nodes) {
    nodes.resize(corners);
    std::sort(nodes.begin(), nodes.end());
    return nodes;
  };
  std::map<std::vector<int>, int> boundary_by_corners;  // sorted corner nodes -> index in boundary
  for (std::size_t f = 0; f < boundary.size(); ++f)
    boundary_by_corners.emplace(corner_key(boundary[f].nodes), static_cast<int>(f));

  std::vector<int> matched;
  for (const RawElement* element : elements) {
    std::vector<int> nodes;
    for (long long tag : content.tags_of(*element)) nodes.push_back(numbering.mesh_node(tag));
    const auto face = boundary_by_corners.find(corner_key(nodes));
    if (face == boundary_by_corners.end())
      in.fail_at(element->line, "physical group '" + MshTokens::excerpt(name) + "' (dimension " + std::to_string(group_dimension) +
                                    "): element " + std::to_string(element->tag) + " (nodes " +
                                    node_list(content.tags_of(*element)) + ") is not a face on the boundary of the mesh");
    matched.push_back(face->second);
  }
  // boundary is in element then local-face order, so sorting indices sorts the faces that way.
  std::sort(matched.begin(), matched.end());
  matched.erase(std::unique(matched.begin(), matched.end()), matched.end());
  std::vector<Face> faces;
  for (int f : matched) faces.push_back(boundary[static_cast<std::size_t>(f)]);
  return faces;
}

void add_physical_groups(const MshTokens& in, const MshContent& content, const NodeNumbering& numbering,
                         Mesh& mesh) {
  // Groups in (dimension, tag) order; their elements in file order.
  std::map<EntityKey, std::vector<const RawElement*>> groups;
  for (const RawElement& element : content.elements) {
    const auto physicals = content.entity_physicals.find(element.entity);
    if (physicals == content.entity_physicals.end()) continue;
    for (int physical : physicals->second) groups[{element.entity.first, physical}].push_back(&element);
  }

  std::map<std::string, int> name_dimension;
  std::vector<Face> boundary;  // the mesh's boundary faces, found for the first face group
  for (const auto& [group, elements] : groups) {
    const std::string name = group_name(content, group);
    const auto [previous, inserted] = name_dimension.emplace(name, group.first);
    if (!inserted)
      throw FemError(in.path() + ": physical name '" + MshTokens::excerpt(name) + "' is used by groups of dimensions " +
                     std::to_string(previous->second) + " and " + std::to_string(group.first));
    std::vector<int> nodes;
    for (const RawElement* element : elements)
      for (long long tag : content.tags_of(*element)) {
        const int node = numbering.mesh_node(tag);
        if (node < 0)
          in.fail_at(element->line, "physical group '" + MshTokens::excerpt(name) + "': node " + std::to_string(tag) + " of element " +
                                        std::to_string(element->tag) + " belongs to no " +
                                        to_string(mesh.element_type) + " element of the mesh");
        nodes.push_back(node);
      }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());

    if (group.first == mesh.dimension() - 1) {
      if (boundary.empty()) boundary = boundary_faces(mesh);
      std::vector<Face> faces = match_boundary_faces(in, content, name, group.first, elements, numbering, mesh, boundary);
      nodes = nodes_of(faces);  // the whole face, also the mid-side node a 2-node line leaves out
      mesh.face_sets[name] = std::move(faces);
    }
    mesh.node_sets[name] = std::move(nodes);
  }
}

}  // namespace

Mesh read_gmsh(const std::string& path) {
  MshTokens in(path);
  const MshContent content = read_sections(in);
  NodeNumbering numbering;
  Mesh mesh = mesh_elements(in, content, numbering);
  flatten_plane_mesh(in, content, numbering, mesh);
  add_physical_groups(in, content, numbering, mesh);
  return mesh;
}

}  // namespace csim
