// ParaView output of finite-element scenes (docs/contract.md): VTK XML UnstructuredGrid files (.vtu,
// Float64, in the encoding of output.paraview: vtk_data_array.h) per output frame, and VTK Collection
// files (.pvd) that give ParaView each frame's real time.
//
//   DIR/paraview/BODY_NNNNNN.vtu      one per frame and elastic body: the reference mesh with point data
//                                     displacement (m) and velocity (m/s); cell data, at each element's
//                                     centroid (element_fields.h): stress (Pa, tension positive: the
//                                     linear law's of the small strain for a linear body, the Cauchy
//                                     stress J⁻¹ P Fᵀ of its law for a finite-strain body), von_mises
//                                     (Pa) and pressure (−tr σ / 3, Pa, compression positive) of it, and
//                                     for a finite-strain body green_lagrange_strain (dimensionless);
//                                     comments before the root element say which stress the file holds;
//   DIR/paraview/contacts_NNNNNN.vtu  one per frame: the active contacts as vertices, with status
//                                     (0 open, 1 stick, 2 slip), impulse over the last step (N·s, on
//                                     the point's body B, in the contact frame: normal, t1, t2) or,
//                                     under the quasi-static stepper, force (N, the same components),
//                                     normal and gap (m) (ContactAction);
//   DIR/paraview/BODY.pvd, contacts.pvd  the collections, written when the run ends.
// The shapes of the other bodies (output.shapes: bodies_NNNNNN.vtp, bodies.pvd) are body_shapes.h's.
//
// The text builders take plain data and return the file's text; ParaviewSeries (paraview_series.h)
// writes them. Points are the reference coordinates: ParaView's "Warp By Vector" on
// displacement shows the deformed shape.
#pragma once

#include "tools/output/element_fields.h"
#include "tools/output/vtk_data_array.h"
#include "engine/state.h"
#include "engine/world.h"
#include "fem/elements.h"
#include "fem/mesh.h"

#include <Eigen/Dense>
#include <optional>
#include <string>
#include <vector>

namespace csim {

// VTK cell type of a mesh's elements: VTK_QUAD (9), VTK_QUADRATIC_QUAD (23) or VTK_HEXAHEDRON (12).
// Our node orders (mesh.h) are VTK's, so connectivity is written as is.
int vtk_cell_type(ElementType type);

// The von Mises equivalent stress (Pa) of (σxx, σyy, σzz, σxy, σyz, σxz) (Pa).
double von_mises(const Stress& stress);
// The mean pressure p = −(σxx + σyy + σzz) / 3 (Pa, compression positive) of the same.
double mean_pressure(const Stress& stress);

// The arrays of a mesh that no frame changes (reference points, m; connectivity, offsets, cell types),
// encoded once per series: compressing them is most of a binary frame's cost otherwise.
struct EncodedMesh {
  VtkEncoding encoding = VtkEncoding::ascii;
  std::size_t points = 0, cells = 0;
  int dofs_per_node = 0;
  EncodedArray coordinates, connectivity, offsets, types;
};
EncodedMesh encode_mesh(const Mesh& mesh, VtkEncoding encoding);

// One elastic body at one frame, in the mesh's encoding, into `file` (opened with mesh.encoding, which
// refers to the mesh's arrays until it is written: ParaviewSeries streams it to the file, VtkFileText::
// write). displacement and velocity: all the mesh's dofs, node-major (m, m/s; 2 or 3 per node as the
// mesh), fields: one stress (and strain, or none) per element, t: the frame's time (s).
void fe_body_file(VtkFileText& file, const EncodedMesh& mesh, const Eigen::VectorXd& displacement,
                  const Eigen::VectorXd& velocity, const ElementFields& fields, double t);
// The same file's text, the mesh encoded for it.
std::string fe_body_vtu(const Mesh& mesh, const Eigen::VectorXd& displacement, const Eigen::VectorXd& velocity,
                        const ElementFields& fields, double t, VtkEncoding encoding);

// What the contacts' files give of each contact's action on the point's body B: the dynamic steppers'
// impulse over the last step (N·s), or the quasi-static stepper's force (N), which its impulses hold
// times the step h (quasi_static.h).
struct ContactAction {
  bool force = false;  // write "force" = impulse / step (N) instead of "impulse" (N·s)
  double step = 0.0;   // s, the h the impulses are taken over (force only)
};

// The contact points at one frame, each at the midpoint of its two surface points (m). Zero contacts give
// a valid empty grid, so that every frame of the series exists.
std::string contacts_vtu(const std::vector<ActiveContact>& contacts, double t, VtkEncoding encoding,
                         const ContactAction& action = {});

// A VTK Collection: one DataSet per frame, file relative to the .pvd's folder, timestep = time (s).
struct CollectionEntry {
  double time = 0.0;  // s
  std::string file;
};
std::string pvd_collection(const std::vector<CollectionEntry>& entries);

}  // namespace csim
