// Strict, located access to a scene's YAML tree.
//
// A SceneNode is a view of one YAML node with its key path ("bodies.shoe.mass") and its document.
// Every read names the key; every map declares the keys it accepts (allow_only), so an unknown or
// misspelt key is an error with file, line and path. Optional values read with a default write that
// default back into the tree, so that the tree, once loaded, is the effective configuration
// (csim dump-config prints it).
//
// Numbers may be written as expressions: a string starting with '=' is evaluated with the scene's
// parameters (and named reference solutions) in scope, e.g. `mass: =2*half_mass`.
#pragma once

#include "tools/scene/expression.h"
#include "tools/scene/scene_error.h"

#include <Eigen/Dense>
#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace csim {

struct SceneDocument {
  std::string file;           // as given by the user, for messages
  YAML::Node root;
  ExpressionScope scope;      // parameters and reference functions
};

class SceneNode {
 public:
  SceneNode(YAML::Node node, std::string path, SceneDocument* document, int line_hint = 0);
  SceneNode(const SceneNode&) = default;
  SceneNode(SceneNode&&) = default;
  // No assignment: YAML::Node's operator= replaces the content of the node it refers to, so assigning
  // one SceneNode to another would rewrite the scene tree (a prescribed {value, until} map once became
  // its value table that way, losing `until` when the tree was read again for a --set on a default).
  SceneNode& operator=(const SceneNode&) = delete;
  SceneNode& operator=(SceneNode&&) = delete;

  const std::string& path() const { return path_; }
  int line() const;
  SceneDocument& document() const { return *document_; }
  const YAML::Node& yaml() const { return node_; }

  [[noreturn]] void fail(const std::string& message) const;
  [[noreturn]] void fail_at(const std::string& key, const std::string& message) const;

  bool is_map() const { return node_.IsMap(); }
  bool is_sequence() const { return node_.IsSequence(); }
  bool is_scalar() const { return node_.IsScalar(); }
  bool has(const std::string& key) const;

  // Children. child() requires the key; optional_child() returns nothing when absent.
  SceneNode child(const std::string& key) const;
  std::optional<SceneNode> optional_child(const std::string& key) const;
  SceneNode section(const std::string& key) const;  // a map child, created empty when absent
  std::vector<std::pair<std::string, SceneNode>> entries() const;  // a map's entries, in file order
  std::vector<SceneNode> items() const;                            // a sequence's items

  void expect_map() const;
  void allow_only(std::initializer_list<const char*> keys) const;
  void allow_only(const std::vector<std::string>& keys) const;

  // This node as a value.
  double as_number() const;
  // The same, but an '=expression' may have no value for these parameters although the scene is well
  // formed: a scope function that fails (a rest time when the mass never stops; why: its message) or a
  // result that is not finite (1/speed at speed 0; why empty). Those give nullopt; malformed text or an
  // unknown name still fail().
  std::optional<double> as_number_if_defined(std::string& why) const;
  std::string as_string() const;
  bool as_bool() const;
  Eigen::Vector3d as_vector(int minimum_size = 1, int maximum_size = 3) const;  // padded with zeros

  // Values of children, required or with a default (written back into the tree when absent).
  double number(const std::string& key) const;
  double number(const std::string& key, double default_value) const;
  std::string string(const std::string& key) const;
  std::string string(const std::string& key, const std::string& default_value) const;
  bool boolean(const std::string& key, bool default_value) const;
  Eigen::Vector3d vector(const std::string& key, int minimum_size = 1, int maximum_size = 3) const;

  // Value checks that fail with the key's location.
  double positive(const std::string& key) const;
  double non_negative(const std::string& key, double default_value) const;
  // A whole number in [least, most] (counts: iterations, steps), required when default_value is empty.
  long whole_number(const std::string& key, std::optional<long> default_value, long least,
                    long most = std::numeric_limits<int>::max()) const;

 private:
  mutable YAML::Node node_;  // mutable: reading a default writes it back (effective configuration)
  std::string path_;
  SceneDocument* document_;
  int line_hint_;  // the parent's line, for nodes that were not in the file
};

// Loads a scene file (throws SceneError naming the file for a missing file, malformed YAML or what
// strict_yaml.h refuses: a duplicate key, a second document, an explicit tag).
SceneDocument load_scene_document(const std::string& file);

// Applies `--set KEY=VALUE`: KEY is a dotted path that must already exist in the file.
void apply_override(SceneDocument& document, const std::string& assignment);

}  // namespace csim
