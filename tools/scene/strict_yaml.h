// What YAML allows and a scene file may not say, refused before the tree is built. yaml-cpp accepts each
// of these silently, and each makes the file mean something other than what its reader sees:
//   a key given twice in one map (yaml-cpp keeps the first: the second, often the later edit, is lost);
//   a second document after '---' (YAML::Load reads the first and drops the rest);
//   an explicit tag other than YAML's core-schema ones (!!str, !!int, !!float, !!bool, !!null, !!seq,
//     !!map): `!python/object` and the like mean nothing to a scene;
//   a key that is not a plain value (a map, a list or an alias as a key), or that holds a control
//     character (a "\e[31m" key would reach the terminal as an escape sequence, through a body's name).
// One pass over the parser's events, linear in the file's size (aliases are not expanded).
#pragma once

#include <string>

namespace csim {

// Throws SceneError naming the file, the line and the key path; malformed YAML as "malformed YAML: ...".
void check_strict_yaml(const std::string& text, const std::string& file);

}  // namespace csim
