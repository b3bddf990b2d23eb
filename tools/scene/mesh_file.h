// Triangle meshes from files, for `{type: mesh, file: ...}` shapes: Wavefront OBJ (`v x y z` and
// `f i j k ...` lines, 1-based or negative indices, `i/t/n` forms, polygons split into a fan from
// their first vertex; other lines ignored) and STL (ASCII `facet ... vertex x y z ...`, or binary:
// 80-byte header, a 32-bit triangle count, 50 bytes a triangle; identical vertices merged). Units:
// the file's numbers are metres.
#pragma once

#include "contact/shape.h"

#include <string>

namespace csim {

// Reads FILE by its extension (.obj or .stl, any case). Throws std::runtime_error whose message names
// the file and, for a malformed text line, its line: "FILE:LINE: reason".
TriangleMesh read_mesh_file(const std::string& file);

}  // namespace csim
