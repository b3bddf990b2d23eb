// The ties of an elastic body's nodes to a rigid body (world.h, RigidTie) as equality rows, for the
// Moreau–Jean stepper, which holds them in its contact problem like any other bilateral constraint.
// (The quasi-static stepper eliminates them instead: reduced_coordinates.h.)
//
// Each free component c of a tied node a gives the constraint
//   g = x_a,c − (x_B + R_B s_a)_c = 0   (m),
// with s_a = R_B,ref⁻¹ (X_a − x_B,ref) the node's place in the hub B's body frame, constant: the node
// stays the hub's material point where it was in the reference configuration. Its row is ∂g/∂v:
// +1 on the node's velocity component, minus row c of the hub's point Jacobian at s_a on the hub's
// velocity components. The rows depend on the hub's rotation, so the stepper linearizes them at each
// iterate and aims at g(q_{k+1}) = 0 (moreau_jean.h). A fixed component of a tied node has no row:
// the scene loader has checked that the hub cannot move it (reduced_coordinates.h).
#pragma once

#include "engine/linear_algebra/sparse_row.h"
#include "engine/world.h"

#include <vector>

namespace csim {

class TieRows {
 public:
  explicit TieRows(const World& world);

  int size() const { return static_cast<int>(entries_.size()); }
  bool empty() const { return entries_.empty(); }
  // The rows ∂g/∂v (velocity components) at positions q.
  void linearize(const Vector& q);
  const std::vector<SparseRow>& rows() const { return rows_; }
  // The gaps g (m) at positions q.
  void compute_gaps(const Vector& q, Vector& gaps) const;

 private:
  struct Entry {
    int node_velocity = -1;  // the node's velocity component in the World
    int node_position = -1;  // its displacement in q
    int component = 0;       // x, y, z
    double reference = 0.0;  // X_a,c (m)
    int hub = -1;            // the rigid body (World index)
    Eigen::Vector3d local = Eigen::Vector3d::Zero();  // s_a (m)
  };
  const World& world_;
  std::vector<Entry> entries_;
  std::vector<SparseRow> rows_;
};

}  // namespace csim
