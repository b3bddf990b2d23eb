#include "tools/scene/scene_node.h"

#include "tools/scene/strict_yaml.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace csim {

namespace {

std::string join_path(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

std::string format_number(double value) {
  std::ostringstream out;
  out.precision(12);
  out << value;
  return out.str();
}

}  // namespace

SceneNode::SceneNode(YAML::Node node, std::string path, SceneDocument* document, int line_hint)
    : node_(std::move(node)), path_(std::move(path)), document_(document), line_hint_(line_hint) {}

int SceneNode::line() const {
  const YAML::Mark mark = node_.Mark();
  return mark.line >= 0 ? mark.line + 1 : line_hint_;
}

void SceneNode::fail(const std::string& message) const {
  throw SceneError(document_->file, line(), path_, message);
}

void SceneNode::fail_at(const std::string& key, const std::string& message) const {
  if (has(key)) child(key).fail(message);
  throw SceneError(document_->file, line(), join_path(path_, key), message);
}

bool SceneNode::has(const std::string& key) const {
  return node_.IsMap() && node_[key].IsDefined() && !node_[key].IsNull();
}

SceneNode SceneNode::child(const std::string& key) const {
  expect_map();
  if (!has(key)) fail_at(key, "missing required key");
  return SceneNode(node_[key], join_path(path_, key), document_, line());
}

std::optional<SceneNode> SceneNode::optional_child(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return child(key);
}

SceneNode SceneNode::section(const std::string& key) const {
  expect_map();
  if (!has(key)) node_[key] = YAML::Node(YAML::NodeType::Map);
  const SceneNode node = child(key);
  node.expect_map();
  return node;
}

std::vector<std::pair<std::string, SceneNode>> SceneNode::entries() const {
  expect_map();
  std::vector<std::pair<std::string, SceneNode>> out;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const std::string key = it->first.as<std::string>();
    out.emplace_back(key, SceneNode(it->second, join_path(path_, key), document_, line()));
  }
  return out;
}

std::vector<SceneNode> SceneNode::items() const {
  if (!node_.IsSequence()) fail("expected a list");
  std::vector<SceneNode> out;
  for (std::size_t i = 0; i < node_.size(); ++i)
    out.emplace_back(node_[i], path_ + "[" + std::to_string(i) + "]", document_, line());
  return out;
}

void SceneNode::expect_map() const {
  if (!node_.IsMap()) fail("expected a map of keys");
}

void SceneNode::allow_only(std::initializer_list<const char*> keys) const {
  allow_only(std::vector<std::string>(keys.begin(), keys.end()));
}

void SceneNode::allow_only(const std::vector<std::string>& keys) const {
  expect_map();
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const std::string key = it->first.as<std::string>();
    bool known = false;
    for (const std::string& k : keys) known = known || key == k;
    if (known) continue;
    std::string expected;
    for (const std::string& k : keys) expected += (expected.empty() ? "" : ", ") + k;
    const int key_line = it->first.Mark().line + 1;
    throw SceneError(document_->file, key_line > 0 ? key_line : line(), join_path(path_, key),
                     "unknown key (expected one of: " + expected + ")");
  }
}

std::optional<double> SceneNode::as_number_if_defined(std::string& why) const {
  if (!node_.IsScalar()) fail("expected a number");
  const std::string text = node_.Scalar();
  double value = 0.0;
  if (!text.empty() && text[0] == '=') {
    try {
      value = evaluate_expression(std::string_view(text).substr(1), document_->scope);
    } catch (const ExpressionFunctionFailed& e) {
      why = e.what();
      return std::nullopt;
    } catch (const ExpressionError& e) {
      fail(std::string("in expression '") + text + "': " + e.what());
    }
    if (!std::isfinite(value)) {
      why.clear();
      return std::nullopt;
    }
    return value;
  }
  std::istringstream in(text);
  in >> value;
  if (in.fail() || !in.eof()) fail("expected a number or an '=expression' (got '" + text + "')");
  if (!std::isfinite(value)) fail("value is not finite ('" + text + "')");
  return value;
}

double SceneNode::as_number() const {
  std::string why;
  const std::optional<double> value = as_number_if_defined(why);
  if (value) return *value;
  const std::string text = node_.Scalar();
  fail(why.empty() ? "value is not finite ('" + text + "')" : "in expression '" + text + "': " + why);
}

std::string SceneNode::as_string() const {
  if (!node_.IsScalar()) fail("expected a text value");
  const std::string text = node_.Scalar();
  if (text.size() > 1 && text[0] == '=') {  // a text parameter; otherwise an expression, kept as written
    const auto it = document_->scope.texts.find(text.substr(1));
    if (it != document_->scope.texts.end()) return it->second;
  }
  return text;
}

bool SceneNode::as_bool() const {
  const std::string text = as_string();
  if (text == "true" || text == "yes" || text == "on") return true;
  if (text == "false" || text == "no" || text == "off") return false;
  fail("expected true or false (got '" + text + "')");
}

Eigen::Vector3d SceneNode::as_vector(int minimum_size, int maximum_size) const {
  if (!node_.IsSequence() || static_cast<int>(node_.size()) < minimum_size ||
      static_cast<int>(node_.size()) > maximum_size)
    fail("expected a list of " +
         (minimum_size == maximum_size ? std::to_string(minimum_size)
                                       : std::to_string(minimum_size) + " to " + std::to_string(maximum_size)) +
         " numbers");
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  const auto list = items();
  for (std::size_t i = 0; i < list.size(); ++i) v(i) = list[i].as_number();
  return v;
}

double SceneNode::number(const std::string& key) const { return child(key).as_number(); }

double SceneNode::number(const std::string& key, double default_value) const {
  expect_map();
  if (has(key)) return child(key).as_number();
  node_[key] = format_number(default_value);
  return default_value;
}

std::string SceneNode::string(const std::string& key) const { return child(key).as_string(); }

std::string SceneNode::string(const std::string& key, const std::string& default_value) const {
  expect_map();
  if (has(key)) return child(key).as_string();
  node_[key] = default_value;
  return default_value;
}

bool SceneNode::boolean(const std::string& key, bool default_value) const {
  expect_map();
  if (has(key)) return child(key).as_bool();
  node_[key] = default_value ? "true" : "false";
  return default_value;
}

Eigen::Vector3d SceneNode::vector(const std::string& key, int minimum_size, int maximum_size) const {
  return child(key).as_vector(minimum_size, maximum_size);
}

double SceneNode::positive(const std::string& key) const {
  const double value = number(key);
  if (!(value > 0.0)) child(key).fail("must be > 0 (got " + format_number(value) + ")");
  return value;
}

double SceneNode::non_negative(const std::string& key, double default_value) const {
  const double value = number(key, default_value);
  if (!(value >= 0.0)) child(key).fail("must be >= 0 (got " + format_number(value) + ")");
  return value;
}

long SceneNode::whole_number(const std::string& key, std::optional<long> default_value, long least,
                             long most) const {
  const double value = default_value ? number(key, static_cast<double>(*default_value)) : number(key);
  if (!(value >= static_cast<double>(least) && value <= static_cast<double>(most)) || value != std::floor(value))
    fail_at(key, most >= std::numeric_limits<int>::max()
                     ? "must be a whole number >= " + std::to_string(least)
                     : "must be a whole number in [" + std::to_string(least) + ", " + std::to_string(most) + "]");
  return static_cast<long>(value);
}

SceneDocument load_scene_document(const std::string& file) {
  SceneDocument document;
  document.file = file;
  std::ifstream in(file);
  if (!in) throw SceneError(file, 0, "", "cannot open the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  check_strict_yaml(text.str(), file);
  try {
    document.root = YAML::Load(text.str());
  } catch (const YAML::Exception& e) {
    throw SceneError(file, e.mark.line + 1, "", "malformed YAML: " + e.msg);
  }
  if (!document.root.IsMap()) throw SceneError(file, 1, "", "a scene must be a map of keys");
  return document;
}

void apply_override(SceneDocument& document, const std::string& assignment) {
  const std::size_t equal = assignment.find('=');
  if (equal == std::string::npos || equal == 0)
    throw SceneError(document.file, 0, assignment, "--set expects KEY=VALUE");
  const std::string path = assignment.substr(0, equal);
  const std::string value = assignment.substr(equal + 1);
  YAML::Node node = document.root;
  std::size_t start = 0;
  std::string walked;
  while (true) {
    const std::size_t dot = path.find('.', start);
    const std::string key = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    walked += (walked.empty() ? "" : ".") + key;
    if (!node.IsMap() || !node[key].IsDefined())
      throw SceneError(document.file, 0, walked, "--set names a key that is not in the scene");
    if (dot == std::string::npos) {
      if (!node[key].IsScalar())
        throw SceneError(document.file, node[key].Mark().line + 1, walked,
                         "--set can only replace a single value");
      node[key] = value;
      return;
    }
    node.reset(node[key]);
    start = dot + 1;
  }
}

}  // namespace csim
