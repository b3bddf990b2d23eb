// DIR/paraview/bodies_NNNNNN.vtp (scene key output.shapes: true; docs/contract.md): the shapes of every
// body that is not elastic (rigid bodies, points, fixed bodies), as a VTK XML PolyData file per output
// frame, in world coordinates (m), in the encoding of output.paraview (vtk_data_array.h).
//
// Each shape is its outline (shape_outlines.h) placed at the body's pose times the shape's local pose;
// a body without shapes (a point) is one vertex at its frame's origin. Cells come in VTK's order:
// those vertices, then lines (a plane scene's halfspaces), then polygons; within each, body by body in
// the scene's order, shape by shape. The file holds
//   point data  velocity       (m/s) the material point's velocity, J(q) v of its body;
//   cell data   body           (Int64) the body's index in the scene's body order;
//               shape          (Int64) the shape's index in its body's shapes, −1 for a point's vertex;
//               body_velocity  (m/s) the velocity of its body frame's origin (the point whose position
//                              bodies.csv gives), zero for a fixed body;
//   field data  TimeValue      (s) the frame's time;
//               body_name      (String) the scene's body names, in its body order: body_name[body].
//
// The bodies drawn move rigidly: the velocity of their material points is affine in the body-frame
// coordinates, u(p) = u(0) + Σ_k p_k (u(e_k) − u(0)) (u = v + ω × R p for a rigid body; a point's and a
// fixed body's are uniform), so a frame keeps four velocities a body, J(q) v at the origin and at the
// three unit points, and the writer thread places every point from them and the pose: it never asks a
// body (whose rotation caches belong to the run's thread).
//
// A halfspace is drawn as a square patch (a segment in a plane scene) centred on the boundary point
// nearest its shape frame's origin, of half side 1.5 times the largest distance from that point to any
// point of the drawn shapes other than halfspaces, any body without shapes and the elastic bodies'
// meshes at t = 0 (1 m when there is none): the patch is the same in every frame, and a body that
// travels far beyond the scene's start leaves it.
#pragma once

#include "tools/output/vtk_data_array.h"
#include "engine/state.h"
#include "engine/world.h"

#include <Eigen/Dense>
#include <cstddef>
#include <string>
#include <vector>

namespace csim {

class BodyShapes {
 public:
  // The outlines in their bodies' frames and the arrays no frame changes (cells, body and shape
  // indices, names), encoded once.
  BodyShapes(const World& world, VtkEncoding encoding);

  // What one frame needs of the state, taken on the run's thread: each drawn body's pose and the
  // velocities (m/s) of its body-frame points 0, e_x, e_y, e_z (columns 0 to 3).
  struct Sample {
    std::vector<Eigen::Isometry3d> poses;
    std::vector<Eigen::Matrix<double, 3, 4>> velocities;
  };
  Sample sample(const State& state) const;

  // The frame's file (the time t in s) into `file`, opened with the series' encoding; `file` refers
  // to this object's arrays until it is written. Reads no body: safe on a writer thread.
  void write(VtkFileText& file, const Sample& sample, double t) const;
  std::string text(const Sample& sample, double t) const;  // the same file as one string

  std::size_t points() const { return local_points_.size(); }
  std::size_t cells() const { return cells_; }

 private:
  const World& world_;
  VtkEncoding encoding_;
  std::vector<int> drawn_;                       // body indices
  std::vector<std::size_t> first_point_;         // per drawn body, then the end: its points' range
  std::vector<Eigen::Vector3d> local_points_;    // m, in their body's frame
  std::vector<std::size_t> cell_body_;           // per cell (VTK's order): its index in drawn_
  std::size_t cells_ = 0, verts_ = 0, lines_ = 0, polys_ = 0;
  std::string field_data_;                       // <FieldData> after TimeValue: the body names
  EncodedArray verts_connectivity_, verts_offsets_, lines_connectivity_, lines_offsets_, polys_connectivity_,
      polys_offsets_, body_, shape_;
};

}  // namespace csim
