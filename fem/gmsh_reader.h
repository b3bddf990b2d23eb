// Import of Gmsh meshes, MSH 4.1 ASCII (gmsh -format msh41; https://gmsh.info/doc/texinfo/gmsh.html,
// section "MSH file format").
//
// What is read:
//   $MeshFormat      must be "4.1 0 <data-size>" (version 4.1, file-type 0 = ASCII);
//   $PhysicalNames   optional: names of the physical groups, keyed by (dimension, tag);
//   $Entities        the physical tags of each point, curve, surface and volume;
//   $Nodes           coordinates (m), node tags in any order and with gaps;
//   $Elements        the mesh elements and the elements of the physical groups below.
//   Other sections ($Periodic, $NodeData, ...) are skipped; $PartitionedEntities is refused.
//
// The mesh. Its elements are the elements of the highest dimension in the file, of one type:
// 3 = quad4, 16 = quad8 (plane meshes) or 5 = hexa8, in file order. Lower-dimensional elements
// (15 = point, 1 = 2-node line, 8 = 3-node line, 3 = quadrilateral as the face of a hexa8 mesh) only
// define physical groups. Nodes are numbered from 0 in file order, keeping only the nodes of the mesh
// elements (a node outside every element would carry degrees of freedom without stiffness). Node
// order within an element is Gmsh's, the one fem/mesh.h uses. Plane meshes must lie in z = 0.
//
// Physical groups, named by their physical name, or "physical_<tag>" when unnamed:
//   every group gives a node set (the sorted nodes of its elements);
//   a group of dimension (mesh dimension − 1) also gives a face set: each of its elements must be a face
//     on the boundary of the mesh (matched by its corner nodes, whatever its node order in the file);
//     the Face takes the owning element, its local face and the outward node order of fem/mesh.h.
//     Faces are sorted by element, then local face.
// Two groups of different dimensions with the same name are an error.
//
// Errors throw FemError naming the file and, where there is one, the line (path:line: ...): file that
// cannot be opened or is not a regular file (refused before opening: a FIFO would block), another version
// or binary file (a binary MSH, or any byte that no text holds: NUL, named with its line and column),
// missing or truncated sections, unreadable numbers, integers out of their field's range (dimensions
// 0-3, counts and Gmsh ints within int, node and element tags ≥ 1 within 64 bits: never narrowed),
// unsupported element types, an element naming an unknown node tag, mixed mesh element types, a face
// group element that is not on the boundary, an element that lists a node twice. A token is quoted to
// its first 40 characters (msh_tokens.h). Jacobian signs are checked by the elements, not here.
//
// The file is read as a stream (msh_tokens.h), never whole: the reader holds the file's records (40 bytes
// a node, 40 an element and 8 per element node) beside the Mesh it builds.
#pragma once

#include "fem/mesh.h"

#include <string>

namespace csim {

Mesh read_gmsh(const std::string& path);

}  // namespace csim
