#include "tools/scene/mesh_file.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace csim {

namespace {

[[noreturn]] void fail(const std::string& file, int line, const std::string& reason) {
  throw std::runtime_error(file + (line > 0 ? ":" + std::to_string(line) : "") + ": " + reason);
}

TriangleMesh read_obj(const std::string& file, std::istream& in) {
  TriangleMesh mesh;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    std::istringstream words(text);
    std::string kind;
    words >> kind;
    if (kind == "v") {
      Eigen::Vector3d x;
      if (!(words >> x.x() >> x.y() >> x.z()) || !x.allFinite()) fail(file, line, "a vertex needs three numbers");
      mesh.vertices.push_back(x);
    } else if (kind == "f") {
      std::vector<int> corners;
      std::string corner;
      while (words >> corner) {
        int index = 0;
        try {
          index = std::stoi(corner.substr(0, corner.find('/')));
        } catch (const std::exception&) {
          fail(file, line, "malformed face index '" + corner + "'");
        }
        const int count = static_cast<int>(mesh.vertices.size());
        const int zero_based = index > 0 ? index - 1 : count + index;  // negative: from the last vertex
        if (index == 0 || zero_based < 0 || zero_based >= count)
          fail(file, line, "face index " + std::to_string(index) + " names no vertex defined before it");
        corners.push_back(zero_based);
      }
      if (corners.size() < 3) fail(file, line, "a face needs at least three vertices");
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) mesh.triangles.push_back({corners[0], corners[k], corners[k + 1]});
    }
  }
  return mesh;
}

// Appends a triangle of STL corners, merging identical vertices.
void add_stl_triangle(const std::array<Eigen::Vector3d, 3>& corners, TriangleMesh& mesh,
                      std::map<std::tuple<double, double, double>, int>& index) {
  std::array<int, 3> triangle;
  for (int k = 0; k < 3; ++k) {
    const auto key = std::make_tuple(corners[k].x(), corners[k].y(), corners[k].z());
    auto [it, added] = index.emplace(key, static_cast<int>(mesh.vertices.size()));
    if (added) mesh.vertices.push_back(corners[k]);
    triangle[k] = it->second;
  }
  mesh.triangles.push_back(triangle);
}

TriangleMesh read_ascii_stl(const std::string& file, std::istream& in) {
  TriangleMesh mesh;
  std::map<std::tuple<double, double, double>, int> index;
  std::array<Eigen::Vector3d, 3> corners;
  int count = 0;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    std::istringstream words(text);
    std::string kind;
    words >> kind;
    if (kind == "vertex") {
      if (count == 3) fail(file, line, "a facet has more than three vertices");
      Eigen::Vector3d& x = corners[count++];
      if (!(words >> x.x() >> x.y() >> x.z()) || !x.allFinite()) fail(file, line, "a vertex needs three numbers");
    } else if (kind == "endfacet") {
      if (count != 3) fail(file, line, "a facet needs three vertices");
      add_stl_triangle(corners, mesh, index);
      count = 0;
    }
  }
  return mesh;
}

TriangleMesh read_binary_stl(const std::string& file, const std::string& bytes) {
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);  // little-endian, as every machine csim runs on
  if (bytes.size() != 84 + 50 * static_cast<std::size_t>(count))
    fail(file, 0, "binary STL of " + std::to_string(bytes.size()) + " bytes does not hold its " + std::to_string(count) +
                      " triangles (84 + 50 each)");
  TriangleMesh mesh;
  std::map<std::tuple<double, double, double>, int> index;
  for (std::uint32_t t = 0; t < count; ++t) {
    std::array<Eigen::Vector3d, 3> corners;
    for (int k = 0; k < 3; ++k) {
      float xyz[3];
      std::memcpy(xyz, bytes.data() + 84 + 50 * t + 12 + 12 * k, 12);  // after the facet normal
      corners[k] = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
      if (!corners[k].allFinite()) fail(file, 0, "triangle " + std::to_string(t) + " has a coordinate that is not finite");
    }
    add_stl_triangle(corners, mesh, index);
  }
  return mesh;
}

}  // namespace

TriangleMesh read_mesh_file(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, 0, "cannot be read");
  std::string extension = file.substr(file.find_last_of('.') == std::string::npos ? file.size() : file.find_last_of('.'));
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  TriangleMesh mesh;
  if (extension == ".obj") {
    mesh = read_obj(file, in);
  } else if (extension == ".stl") {
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // ASCII STL starts with "solid" and holds "facet"; a binary header may start with "solid" too.
    if (bytes.rfind("solid", 0) == 0 && bytes.find("facet") != std::string::npos) {
      std::istringstream text(bytes);
      mesh = read_ascii_stl(file, text);
    } else if (bytes.size() >= 84) {
      mesh = read_binary_stl(file, bytes);
    } else {
      fail(file, 0, "neither an ASCII STL nor a binary one (shorter than its 84-byte header)");
    }
  } else {
    fail(file, 0, "unknown mesh format '" + extension + "' (expected .obj or .stl)");
  }
  if (mesh.triangles.empty()) fail(file, 0, "holds no triangle");
  return mesh;
}

}  // namespace csim
