// What YAML allows and a scene may not say: each case names the file, the line(s) and the key path.
#include "tools/scene/strict_yaml.h"

#include "tools/scene/scene_error.h"

#include <gtest/gtest.h>

#include <string>

namespace csim {
namespace {

// The SceneError message for `text`, or "" when it passes.
std::string refusal(const std::string& text) {
  try {
    check_strict_yaml(text, "scene.yaml");
  } catch (const SceneError& error) {
    return error.what();
  }
  return "";
}

TEST(StrictYaml, PlainScenesPass) {
  EXPECT_EQ(refusal("dimension: 2\nbodies:\n  a: {type: point, mass: 1}\n  b: {type: point, mass: 1}\n"), "");
  EXPECT_EQ(refusal("probes: [{a: 1}, {a: 2}]\nlist: [1, 1, 1]\n"), "");  // same keys in different maps
  EXPECT_EQ(refusal("---\ndimension: 2\n...\n"), "");                    // one document, with its markers
  EXPECT_EQ(refusal("a: !!int 2\nb: !!str x\nc: !!float 1\nd: !!map {e: !!seq [1]}\nf: 'quoted'\n"), "");
  EXPECT_EQ(refusal("a: &shared {x: 1}\nb: *shared\n"), "");  // aliases as values are plain YAML
  EXPECT_EQ(refusal(""), "");
}

TEST(StrictYaml, DuplicateKeysNameThePathAndBothLines) {
  EXPECT_EQ(refusal("parameters:\n  mass: 1\n  mu: 0.3\n  mass: 2\n"),
            "scene.yaml:4: parameters.mass: key given twice, on lines 2 and 4 (YAML would keep one and drop the "
            "other silently)");
  EXPECT_NE(refusal("time: 1\nbodies: {}\ntime: 2\n").find("scene.yaml:3: time: key given twice, on lines 1 and 3"),
            std::string::npos);
  EXPECT_NE(refusal("bodies:\n  a: {mass: 1, mass: 2}\n").find("bodies.a.mass: key given twice, both on line 2"),
            std::string::npos);
  EXPECT_NE(refusal("checks:\n  x: [{a: 1}, {a: 1, b: 2, \"a\": 3}]\n").find("checks.x[1].a: key given twice"),
            std::string::npos);
}

TEST(StrictYaml, OneDocumentOnly) {
  EXPECT_EQ(refusal("dimension: 2\n---\ndimension: 3\n"),
            "scene.yaml:2: a second YAML document ('---'): a scene file holds one document");
}

TEST(StrictYaml, ExplicitTagsAreRefused) {
  EXPECT_NE(refusal("bodies:\n  a: {mass: !python/object:builtins.float 1}\n")
                .find("scene.yaml:2: bodies.a.mass: explicit YAML tag '!python/object:builtins.float'"),
            std::string::npos);
  EXPECT_NE(refusal("bodies:\n  a: !custom {mass: 1}\n").find("bodies.a: explicit YAML tag '!custom'"),
            std::string::npos);
  EXPECT_NE(refusal("a: !!python/tuple [1, 2]\n").find("a: explicit YAML tag 'tag:yaml.org,2002:python/tuple'"),
            std::string::npos);
}

TEST(StrictYaml, KeysArePlainNames) {
  EXPECT_NE(refusal("? [a, b]\n: 1\n").find("a map or a list as a key"), std::string::npos);
  EXPECT_NE(refusal("a: &k x\n*k : 1\n").find("an alias as a key"), std::string::npos);
}

TEST(StrictYaml, KeysHoldNoControlCharacters) {
  EXPECT_NE(refusal("bodies:\n  \"\\e[31mblock\": {mass: 1}\n").find("a key with a control character"),
            std::string::npos);
  EXPECT_EQ(refusal("bodies:\n  θ_block: {μ: 1}\n"), "");
}

TEST(StrictYaml, MalformedYamlNamesTheLine) {
  EXPECT_NE(refusal("a: 1\nb: [1, 2\n").find("malformed YAML"), std::string::npos);
}

}  // namespace
}  // namespace csim
