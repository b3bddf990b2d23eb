#include "tools/scene/strict_yaml.h"

#include "tools/scene/scene_error.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <map>
#include <sstream>
#include <vector>

namespace csim {

namespace {

bool is_allowed_tag(const std::string& tag) {
  // "?": no tag (a plain scalar, a collection); "!": the non-specific tag of a quoted scalar.
  if (tag.empty() || tag == "?" || tag == "!") return true;
  static const std::string core = "tag:yaml.org,2002:";
  if (tag.compare(0, core.size(), core) != 0) return false;
  const std::string name = tag.substr(core.size());
  return name == "str" || name == "int" || name == "float" || name == "bool" || name == "null" || name == "seq" ||
         name == "map";
}

// Follows the key path through the events; maps remember where each of their keys was given.
class StrictHandler : public YAML::EventHandler {
 public:
  explicit StrictHandler(const std::string& file) : file_(file) {}

  void OnDocumentStart(const YAML::Mark& mark) override {
    if (++documents_ > 1)
      fail(mark, "", "a second YAML document ('---'): a scene file holds one document");
  }
  void OnDocumentEnd() override {}

  void OnNull(const YAML::Mark& mark, YAML::anchor_t) override {
    if (at_key()) fail(mark, path_of_container(), "an empty key");
    value_seen();
  }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override {
    if (at_key()) fail(mark, path_of_container(), "an alias as a key: a key must be a plain name");
    value_seen();
  }
  void OnScalar(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t, const std::string& value) override {
    if (at_key()) {
      key(mark, tag, value);
      return;
    }
    check_tag(mark, tag, path_of_value());
    value_seen();
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {
    open(mark, tag, false);
  }
  void OnSequenceEnd() override { close(); }
  void OnMapStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t, YAML::EmitterStyle::value) override {
    open(mark, tag, true);
  }
  void OnMapEnd() override { close(); }

 private:
  struct Container {
    bool is_map = false;
    std::string path;
    std::map<std::string, int> key_lines;  // map: each key and its 1-based line
    bool at_key = true;                    // map: the next node is a key
    std::string key;                       // map: the key of the value being read
    int index = 0;                         // sequence: of the next item
  };

  bool at_key() const { return !open_.empty() && open_.back().is_map && open_.back().at_key; }

  std::string path_of_container() const { return open_.empty() ? std::string() : open_.back().path; }

  std::string path_of_value() const {
    if (open_.empty()) return "";
    const Container& c = open_.back();
    if (!c.is_map) return c.path + "[" + std::to_string(c.index) + "]";
    return c.path.empty() ? c.key : c.path + "." + c.key;
  }

  void value_seen() {
    if (open_.empty()) return;
    Container& c = open_.back();
    if (c.is_map) c.at_key = true;
    else ++c.index;
  }

  void key(const YAML::Mark& mark, const std::string& tag, const std::string& name) {
    Container& c = open_.back();
    c.key = name;
    c.at_key = false;
    const std::string path = path_of_value();
    check_tag(mark, tag, path);
    // A key is often a name that reaches the terminal and the output files (a body, a probe, a check).
    auto control = [](char ch) { return static_cast<unsigned char>(ch) < 0x20 || ch == 0x7F; };
    if (std::any_of(name.begin(), name.end(), control))
      fail(mark, path, "a key with a control character: keys are printable text");
    const int line = mark.line + 1;
    const auto [first, inserted] = c.key_lines.emplace(name, line);
    if (!inserted)
      fail(mark, path,
           "key given twice, " +
               (first->second == line ? "both on line " + std::to_string(line)
                                      : "on lines " + std::to_string(first->second) + " and " + std::to_string(line)) +
               " (YAML would keep one and drop the other silently)");
  }

  void open(const YAML::Mark& mark, const std::string& tag, bool is_map) {
    if (at_key()) fail(mark, path_of_container(), "a map or a list as a key: a key must be a plain name");
    const std::string path = path_of_value();
    check_tag(mark, tag, path);
    Container c;
    c.is_map = is_map;
    c.path = path;
    open_.push_back(std::move(c));
  }

  void close() {
    open_.pop_back();
    value_seen();
  }

  void check_tag(const YAML::Mark& mark, const std::string& tag, const std::string& path) const {
    if (!is_allowed_tag(tag))
      fail(mark, path,
           "explicit YAML tag '" + tag + "': a scene takes plain values (tags allowed: YAML's core !!str, !!int, "
                                         "!!float, !!bool, !!null, !!seq, !!map)");
  }

  [[noreturn]] void fail(const YAML::Mark& mark, const std::string& path, const std::string& message) const {
    throw SceneError(file_, mark.line + 1, path, message);
  }

  std::string file_;
  int documents_ = 0;
  std::vector<Container> open_;
};

}  // namespace

void check_strict_yaml(const std::string& text, const std::string& file) {
  std::istringstream in(text);
  StrictHandler handler(file);
  try {
    YAML::Parser parser(in);
    while (parser.HandleNextDocument(handler)) {
    }
  } catch (const YAML::Exception& e) {
    throw SceneError(file, e.mark.line + 1, "", "malformed YAML: " + e.msg);
  }
}

}  // namespace csim
