// The unknowns of the quasi-static stepper: the World's coordinates q (n entries) as a function of
// fewer unknowns z (nz entries) and of time, q = Φ(z, t):
//   a free component is an unknown;
//   a prescribed one (world.h, PrescribedComponent) is q_ref + value(t), while it is active (a
//   released one is free: the stepper builds new reduced coordinates when the set changes);
//   an elastic body with a tie (world.h, RigidTie) rides in the frame of its rigid body B (a floating
//   frame): its node a is at x_a = x_B + R(φ_B − φ_B,ref)(a + w_a), a = X_a − x_B,ref its arm in the
//   reference configuration (m), and its unknowns are w_a, the displacements in B's frame; the tied
//   nodes have w_a = 0.
// Why a floating frame rather than only the tied nodes following B: the strain energy is exactly
// invariant under B's rotation, so the rigid rotation of a stressed ring costs nothing in K_z, as in
// the continuum. With the free nodes in world coordinates, Newton's linearization sees along that
// rotation the stiffness −Σ r·(x − x_B) of the contact forces r (a node moving along its tangent
// leaves the circle), −N (R − δ) for a wheel pressed by N: negative, and the iteration diverges.
// Newton's method on z needs T = ∂Φ/∂z (n × nz) and, for the equilibrium Tᵀ f(q) = 0 with f the
// generalized force (N, N·m), the reduced tangent
//   K_z = Tᵀ K T − Σ_i f_i ∂²Φ_i/∂z²,   ∂²x_a/∂φ² = −R (a + w_a),  ∂²x_a/∂φ∂w_a = J R  (J = e_z ×),
// whose second term is the frame's geometric stiffness. Units: q as the bodies' (m, rad); z the same.
#pragma once

#include "engine/sparse_row.h"
#include "engine/world.h"

#include <array>
#include <vector>

namespace csim {

class ReducedCoordinates {
 public:
  // Throws std::invalid_argument (the caller reports it) for a component prescribed twice, a tied body
  // with fixed nodes or two ties, or a tie to a body that is not a plane rigid body.
  // The prescriptions active at time t (PrescribedComponent::until).
  ReducedCoordinates(const World& world, double t);

  int size() const { return unknown_count_; }
  bool identity() const { return identity_; }  // nothing prescribed or tied: z = q
  // The unknown of component i of q, or −1 (prescribed or tied).
  int unknown(int i) const { return unknown_of_[i]; }
  bool prescribed(int i) const { return prescription_of_[i] >= 0; }
  // Unknowns that belong to a rigid body carrying tied nodes (a hub): their stiffness comes only through
  // the ring, which a rigid-body mode of the ring leaves without (see quasi_static.h).
  const std::vector<int>& hub_unknowns() const { return hub_unknowns_; }

  void gather(const Vector& q, Vector& z) const;              // z ← the unknowns' entries of q
  void expand(const Vector& z, double t, Vector& q) const;    // q ← Φ(z, t)
  // The generalized force f (N, N·m, in q's components) on each prescribed component, through every
  // coordinate that moves with it (a hub's spin carries its ring's nodes): ∂Φ/∂p ᵀ f, p the
  // prescribed coordinate; zero on the other components.
  void prescribed_forces(const Vector& q, const Vector& f, Vector& forces) const;
  // T at q (the floating bodies' columns depend on q, through their frame's angle).
  void tangent(const Vector& q, SparseMatrix& T) const;
  // K_z = Tᵀ K T − Σ f_i ∂²Φ_i/∂z² (T from tangent(q), f the generalized force at q).
  void reduce_stiffness(const SparseMatrix& K, const SparseMatrix& T, const Vector& q, const Vector& f,
                        SparseMatrix& K_z) const;

 private:
  // A node of a body riding in a rigid body's frame.
  struct Floating {
    std::array<int, 2> dof{};     // its x, y entries of q
    std::array<int, 2> unknown{}; // its w entries of z, −1 for a tied node
    Eigen::Vector2d arm;          // a = X_a − x_B,ref (m)
    int rigid_offset = 0;         // position offset of the rigid body (x, y, φ)
    double angle_ref = 0.0;       // φ_B,ref (rad)
    Eigen::Vector2d centre_ref;   // x_B,ref (m)
  };
  // The frame's rotation R(φ − φ_ref) at q.
  Eigen::Matrix2d frame(const Floating& node, const Vector& q) const;
  Eigen::Vector2d current_arm(const Floating& node, const Vector& q) const;  // x_a − x_B = R (a + w_a), m
  const World* world_;  // a pointer, so that a stepper can rebuild its reduced coordinates
  int unknown_count_ = 0;
  bool identity_ = true;
  std::vector<int> unknown_of_, prescription_of_, floating_of_;  // per q component; −1 when not
  std::vector<Floating> floating_;
  std::vector<int> hub_unknowns_;
};

}  // namespace csim
