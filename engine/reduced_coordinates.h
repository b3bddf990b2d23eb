// The unknowns of the quasi-static stepper: the World's coordinates q (n entries) as a function of
// fewer unknowns z (nz entries) and of time,
//   q = Φ(z, t):   a free component is an unknown;
//                  a prescribed one (world.h, PrescribedComponent) is q_ref + value(t);
//                  a component of a node tied to a rigid body (world.h, RigidTie) follows that body,
//                  nonlinearly in its angle: u_a = x_B − x_B,ref + (R(φ_B − φ_B,ref) − I) a, with
//                  a = X_a − x_B,ref the node's arm in the reference configuration (m).
// Newton's method on z needs T = ∂Φ/∂z (n × nz) and, for the equilibrium Tᵀ f(q) = 0 with f the
// generalized force (N, N·m), the reduced tangent
//   K_z = Tᵀ K T − Σ_i f_i ∂²Φ_i/∂z²,   ∂²u_a/∂φ² = −R a,
// whose second term is the ties' geometric stiffness (the force a tied node carries turning with its
// arm). Units: q as the bodies' (m, rad); z the same components.
#pragma once

#include "engine/sparse_row.h"
#include "engine/world.h"

#include <vector>

namespace csim {

class ReducedCoordinates {
 public:
  // Throws std::invalid_argument (the caller reports it) for a component prescribed twice, a tied node
  // that is fixed or tied twice, or a tie to a body that is not a plane rigid body.
  explicit ReducedCoordinates(const World& world);

  int size() const { return unknown_count_; }
  bool identity() const { return identity_; }  // nothing prescribed or tied: z = q
  bool has_ties() const { return !world_.ties.empty(); }
  // The unknown of component i of q, or −1 (prescribed or tied).
  int unknown(int i) const { return unknown_of_[i]; }
  bool prescribed(int i) const { return prescription_of_[i] >= 0; }
  // Unknowns that belong to a rigid body carrying tied nodes (a hub): their stiffness comes only through
  // the ring, which a rigid-body mode of the ring leaves without (see quasi_static.h).
  const std::vector<int>& hub_unknowns() const { return hub_unknowns_; }

  void gather(const Vector& q, Vector& z) const;              // z ← the unknowns' entries of q
  void expand(const Vector& z, double t, Vector& q) const;    // q ← Φ(z, t)
  // T at q (only the tied nodes' columns depend on q, through the hub's angle).
  void tangent(const Vector& q, SparseMatrix& T) const;
  // K_z = Tᵀ K T − Σ f_i ∂²Φ_i/∂z² (T from tangent(q), f the generalized force at q).
  void reduce_stiffness(const SparseMatrix& K, const SparseMatrix& T, const Vector& q, const Vector& f,
                        SparseMatrix& K_z) const;

 private:
  struct Tied {
    int tie = -1;                 // index in world.ties
    int component = 0;            // 0: x, 1: y
    Eigen::Vector2d arm;          // a = X_a − x_B,ref (m)
    int rigid_offset = 0;         // position offset of the rigid body (x, y, φ)
  };
  const World& world_;
  int unknown_count_ = 0;
  bool identity_ = true;
  std::vector<int> unknown_of_, prescription_of_, tied_of_;  // per q component; −1 when not
  std::vector<Tied> tied_;
  std::vector<int> hub_unknowns_;
};

}  // namespace csim
