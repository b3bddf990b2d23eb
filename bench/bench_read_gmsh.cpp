// Reads one Gmsh mesh with read_gmsh and prints its size: the reader's own peak memory, measured with
//   /usr/bin/time -f %M build/bench/bench_read_gmsh MESH.msh
// (bench/gmsh_memory.py writes a large mesh and runs it).
#include "fem/gmsh_reader.h"

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: bench_read_gmsh MESH.msh\n");
    return 2;
  }
  try {
    const csim::Mesh mesh = csim::read_gmsh(argv[1]);
    std::printf("%zu nodes, %zu elements\n", mesh.nodes.size(), mesh.elements.size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  return 0;
}
