// Gmsh MSH 4.1 ASCII import, in two passes: read the sections into plain records (keeping the line of
// every node and element for the messages), then build the Mesh, its node sets and face sets.
#include "fem/gmsh_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace csim {
namespace {

// ----- tokens with line numbers ---------------------------------------------------------------------

// Whitespace-separated tokens of the file; every failure names the file and the current line.
class MshTokens {
 public:
  explicit MshTokens(const std::string& path) : path_(path) {
    // Before opening: a FIFO would block, a device be read without end, a directory read as empty.
    std::error_code error;
    const std::filesystem::file_status status = std::filesystem::status(path, error);
    if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
      throw FemError(path + ": not a regular file (a directory, a FIFO or a device holds no Gmsh mesh)");
    std::ifstream file(path);
    if (!file) throw FemError(path + ": cannot open the Gmsh mesh file");
    for (std::string line; std::getline(file, line);) lines_.push_back(std::move(line));
  }

  const std::string& path() const { return path_; }
  // The line of the current position, 1-based; at the end of the file, its last line.
  int line() const { return static_cast<int>(std::min(line_ + 1, std::max<std::size_t>(lines_.size(), 1))); }

  // The line of the next token (or the last line at the end of the file).
  int token_line() {
    skip_space();
    return line();
  }

  bool at_end() {
    skip_space();
    return line_ >= lines_.size();
  }

  // The next token; `what` says what was expected, for the message at the end of the file.
  std::string word(const std::string& what) {
    if (at_end()) fail("unexpected end of file while reading " + what + " (truncated file?)");
    const std::string& text = lines_[line_];
    const std::size_t begin = pos_;
    while (pos_ < text.size() && !is_space(text[pos_])) ++pos_;
    return text.substr(begin, pos_ - begin);
  }

  long long integer(const std::string& what) {
    const std::string token = word(what);
    long long value = 0;
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (error != std::errc() || end != token.data() + token.size())
      fail("expected an integer (" + what + "), found '" + token + "'");
    return value;
  }

  // A count or an index that must fit an int and not be negative.
  int count(const std::string& what) {
    const long long value = integer(what);
    if (value < 0 || value > std::numeric_limits<int>::max())
      fail(what + " " + std::to_string(value) + " is out of range");
    return static_cast<int>(value);
  }

  double real(const std::string& what) {
    const std::string token = word(what);
    double value = 0.0;
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (error != std::errc() || end != token.data() + token.size() || !std::isfinite(value))
      fail("expected a finite number (" + what + "), found '" + token + "'");
    return value;
  }

  // A double-quoted name as in $PhysicalNames (it may contain spaces).
  std::string quoted(const std::string& what) {
    if (at_end() || lines_[line_][pos_] != '"') fail("expected a quoted " + what);
    const std::string& text = lines_[line_];
    const std::size_t close = text.find('"', pos_ + 1);
    if (close == std::string::npos) fail("unterminated quoted " + what);
    std::string value = text.substr(pos_ + 1, close - pos_ - 1);
    pos_ = close + 1;
    return value;
  }

  void expect(const std::string& marker) {
    const std::string token = word(marker);
    if (token != marker) fail("expected " + marker + ", found '" + token + "'");
  }

  // Skips a section we do not read, up to its end marker.
  void skip_section(const std::string& name) {
    const std::string end = "$End" + name.substr(1);
    for (std::string token = word(end); token != end; token = word(end)) {
    }
  }

  [[noreturn]] void fail(const std::string& message) const { fail_at(line(), message); }
  [[noreturn]] void fail_at(int line, const std::string& message) const {
    throw FemError(path_ + ":" + std::to_string(line) + ": " + message);
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

  void skip_space() {
    while (line_ < lines_.size()) {
      const std::string& text = lines_[line_];
      while (pos_ < text.size() && is_space(text[pos_])) ++pos_;
      if (pos_ < text.size()) return;
      ++line_;
      pos_ = 0;
    }
  }

  std::string path_;
  std::vector<std::string> lines_;
  std::size_t line_ = 0;
  std::size_t pos_ = 0;
};

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

struct RawElement {
  long long tag;
  const ElementKind* kind;
  EntityKey entity;
  std::vector<long long> node_tags;
  int line;
};

struct MshContent {
  std::map<EntityKey, std::string> physical_names;
  std::map<EntityKey, std::vector<int>> entity_physicals;  // physical tags of each entity
  std::vector<RawNode> nodes;
  std::vector<RawElement> elements;
};

std::string node_list(const std::vector<long long>& tags) {
  std::string text;
  for (long long tag : tags) text += (text.empty() ? "" : " ") + std::to_string(tag);
  return text;
}

// ----- sections -------------------------------------------------------------------------------------

void read_mesh_format(MshTokens& in) {
  const std::string version = in.word("the MSH version");
  if (version != "4.1")
    in.fail("MSH version " + version + ": only MSH 4.1 ASCII is supported (gmsh -format msh41)");
  const std::string file_type = in.word("the MSH file type");
  if (file_type != "0") in.fail("binary MSH (file type " + file_type + "): only MSH 4.1 ASCII is supported");
  in.integer("the MSH data size");
  in.expect("$EndMeshFormat");
}

void read_physical_names(MshTokens& in, MshContent& content) {
  const int count = in.count("the number of physical names");
  for (int i = 0; i < count; ++i) {
    const int dimension = in.count("a physical group dimension");
    const int tag = static_cast<int>(in.integer("a physical tag"));
    content.physical_names[{dimension, tag}] = in.quoted("physical name");
  }
  in.expect("$EndPhysicalNames");
}

void read_entities(MshTokens& in, MshContent& content) {
  int counts[4];
  for (int& count : counts) count = in.count("the number of entities of one dimension");
  for (int dimension = 0; dimension < 4; ++dimension)
    for (int i = 0; i < counts[dimension]; ++i) {
      const int tag = static_cast<int>(in.integer("an entity tag"));
      const int coordinates = dimension == 0 ? 3 : 6;  // a point, or the bounding box of a curve, ...
      for (int k = 0; k < coordinates; ++k) in.real("entity coordinates");
      std::vector<int>& physicals = content.entity_physicals[{dimension, tag}];
      const int physical_count = in.count("the number of physical tags of an entity");
      for (int k = 0; k < physical_count; ++k) physicals.push_back(static_cast<int>(in.integer("a physical tag")));
      if (dimension > 0) {
        const int bounding = in.count("the number of bounding entities");
        for (int k = 0; k < bounding; ++k) in.integer("a bounding entity tag");
      }
    }
  in.expect("$EndEntities");
}

void read_nodes(MshTokens& in, MshContent& content) {
  const int blocks = in.count("the number of node blocks");
  const int total = in.count("the number of nodes");
  in.integer("the smallest node tag");
  in.integer("the largest node tag");
  for (int block = 0; block < blocks; ++block) {
    const int entity_dimension = in.count("the entity dimension of a node block");
    in.integer("the entity tag of a node block");
    const long long parametric = in.integer("the parametric flag of a node block");
    const int in_block = in.count("the number of nodes in a block");
    const std::size_t first = content.nodes.size();
    for (int i = 0; i < in_block; ++i) {
      const int line = in.token_line();
      content.nodes.push_back(RawNode{in.integer("a node tag"), Eigen::Vector3d::Zero(), line});
    }
    // Parametric nodes carry their parametric coordinates (u, v, w up to the entity dimension).
    const int extra = parametric != 0 ? entity_dimension : 0;
    for (int i = 0; i < in_block; ++i) {
      Eigen::Vector3d& x = content.nodes[first + static_cast<std::size_t>(i)].x;
      for (int k = 0; k < 3; ++k) x(k) = in.real("node coordinates");
      for (int k = 0; k < extra; ++k) in.real("parametric node coordinates");
    }
  }
  if (static_cast<int>(content.nodes.size()) != total)
    in.fail("$Nodes announces " + std::to_string(total) + " nodes, its blocks hold " +
            std::to_string(content.nodes.size()));
  in.expect("$EndNodes");
}

void read_elements(MshTokens& in, MshContent& content) {
  const int blocks = in.count("the number of element blocks");
  const int total = in.count("the number of elements");
  in.integer("the smallest element tag");
  in.integer("the largest element tag");
  const std::size_t first = content.elements.size();
  for (int block = 0; block < blocks; ++block) {
    const int entity_dimension = in.count("the entity dimension of an element block");
    const int entity_tag = static_cast<int>(in.integer("the entity tag of an element block"));
    const int gmsh_type = static_cast<int>(in.integer("the element type of an element block"));
    const ElementKind* kind = find_kind(gmsh_type);
    if (kind == nullptr)
      in.fail("element type " + std::to_string(gmsh_type) +
              " is not supported (supported: 15 point, 1 and 8 lines, 3 and 16 quadrangles, 5 hexahedron)");
    if (kind->dimension != entity_dimension)
      in.fail(std::string("a block of ") + kind->name + " elements on an entity of dimension " +
              std::to_string(entity_dimension));
    const int in_block = in.count("the number of elements in a block");
    for (int i = 0; i < in_block; ++i) {
      RawElement element{0, kind, {entity_dimension, entity_tag}, {}, in.token_line()};
      element.tag = in.integer("an element tag");
      for (int k = 0; k < kind->node_count; ++k) element.node_tags.push_back(in.integer("an element node tag"));
      // A repeated node collapses the element (a quadrangle 1 2 2 3 is a triangle) and its collapsed
      // edge or face matches no neighbour's: a hole in the mesh, which the Jacobians need not show.
      std::vector<long long> sorted = element.node_tags;
      std::sort(sorted.begin(), sorted.end());
      if (const auto twice = std::adjacent_find(sorted.begin(), sorted.end()); twice != sorted.end())
        in.fail_at(element.line, "element " + std::to_string(element.tag) + " (" + kind->name + ", nodes " +
                                     node_list(element.node_tags) + ") lists node " + std::to_string(*twice) +
                                     " twice: a degenerate element leaves a hole in the mesh");
      content.elements.push_back(std::move(element));
    }
  }
  if (static_cast<int>(content.elements.size() - first) != total)
    in.fail("$Elements announces " + std::to_string(total) + " elements, its blocks hold " +
            std::to_string(content.elements.size() - first));
  in.expect("$EndElements");
}

MshContent read_sections(MshTokens& in) {
  MshContent content;
  std::set<std::string> seen;
  while (!in.at_end()) {
    const std::string section = in.word("a section");
    if (section.empty() || section[0] != '$') in.fail("expected a section such as $Nodes, found '" + section + "'");
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
  std::unordered_map<long long, int> position;  // node tag -> position in $Nodes (lookup only)
  std::vector<int> index;                       // position -> mesh node, −1 outside the mesh elements

  int mesh_node(long long tag) const { return index[static_cast<std::size_t>(position.at(tag))]; }
};

// The elements of the highest dimension, of one type, and their nodes.
Mesh mesh_elements(const MshTokens& in, const MshContent& content, NodeNumbering& numbering) {
  int dimension = -1;
  for (const RawElement& element : content.elements) dimension = std::max(dimension, element.kind->dimension);
  if (dimension < 2)
    throw FemError(in.path() + ": no quadrangle or hexahedron elements (Gmsh saves only the elements of physical "
                               "groups when there are any: add a physical surface or volume)");

  for (std::size_t i = 0; i < content.nodes.size(); ++i)
    if (!numbering.position.emplace(content.nodes[i].tag, static_cast<int>(i)).second)
      in.fail_at(content.nodes[i].line, "node tag " + std::to_string(content.nodes[i].tag) + " appears twice");
  for (const RawElement& element : content.elements)
    for (long long tag : element.node_tags)
      if (numbering.position.count(tag) == 0)
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
    for (long long tag : element.node_tags) used[static_cast<std::size_t>(numbering.position.at(tag))] = true;
  }
  numbering.index.assign(content.nodes.size(), -1);
  for (std::size_t i = 0; i < content.nodes.size(); ++i)
    if (used[i]) {
      numbering.index[i] = static_cast<int>(mesh.nodes.size());
      mesh.nodes.push_back(content.nodes[i].x);
    }
  for (const RawElement& element : content.elements) {
    if (element.kind->dimension != dimension) continue;
    std::vector<int> nodes;
    for (long long tag : element.node_tags) nodes.push_back(numbering.mesh_node(tag));
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
std::vector<Face> match_boundary_faces(const MshTokens& in, const std::string& name, int group_dimension,
                                       const std::vector<const RawElement*>& elements,
                                       const NodeNumbering& numbering, const Mesh& mesh) {
  const std::vector<Face> boundary = boundary_faces(mesh);
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
    for (long long tag : element->node_tags) nodes.push_back(numbering.mesh_node(tag));
    const auto face = boundary_by_corners.find(corner_key(nodes));
    if (face == boundary_by_corners.end())
      in.fail_at(element->line, "physical group '" + name + "' (dimension " + std::to_string(group_dimension) +
                                    "): element " + std::to_string(element->tag) + " (nodes " +
                                    node_list(element->node_tags) + ") is not a face on the boundary of the mesh");
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
  for (const auto& [group, elements] : groups) {
    const std::string name = group_name(content, group);
    const auto [previous, inserted] = name_dimension.emplace(name, group.first);
    if (!inserted)
      throw FemError(in.path() + ": physical name '" + name + "' is used by groups of dimensions " +
                     std::to_string(previous->second) + " and " + std::to_string(group.first));
    std::vector<int> nodes;
    for (const RawElement* element : elements)
      for (long long tag : element->node_tags) {
        const int node = numbering.mesh_node(tag);
        if (node < 0)
          in.fail_at(element->line, "physical group '" + name + "': node " + std::to_string(tag) + " of element " +
                                        std::to_string(element->tag) + " belongs to no " +
                                        to_string(mesh.element_type) + " element of the mesh");
        nodes.push_back(node);
      }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());

    if (group.first == mesh.dimension() - 1) {
      std::vector<Face> faces = match_boundary_faces(in, name, group.first, elements, numbering, mesh);
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
