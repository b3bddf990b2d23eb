// The unknowns of the quasi-static stepper: the World's configuration q as a function of fewer
// unknowns z (nz entries) and of time, q = Φ(z, t). z is laid out over the World's velocity
// components (the coordinates of a 3D rigid body's rotation are a quaternion, its unknowns three
// angles):
//   a free component is an unknown;
//   a prescribed one (world.h, PrescribedComponent) is q_ref + value(t), while it is active (a
//   released one is free: the stepper builds new reduced coordinates when the set changes);
//   the rotation of a 3D rigid body (a unit quaternion) is moved from a base configuration, the q
//   given to the last gather(): its unknowns are the angles Δ turned about its body axes (rad),
//   R = R_base exp([Δ]); a prescribed rotation component
//   turns it by value(t) − value(t_base) about that body axis (exact for a turn about one fixed axis,
//   a ground turning about a vertical axis, the only use so far). The stepper gathers at every
//   Newton iterate, so T below is exact there;
//   an elastic body with a tie (world.h, RigidTie) rides in the frame of its rigid body B (a floating
//   frame): its node a is at x_a = x_B + R_rel (a + w_a), R_rel = R_B R_B,ref⁻¹ the hub's rotation
//   since the reference, a = X_a − x_B,ref its arm in the reference configuration (m), and its
//   unknowns are w_a, the displacements in B's frame; the tied nodes have w_a = 0. A tied body may
//   have fixed components (plane strain across a 3D ring: z held) only where B's frame cannot move
//   them: B's translation along that axis and its rotations about the other axes prescribed at 0.
// Why a floating frame rather than only the tied nodes following B: the strain energy is exactly
// invariant under B's rotation, so the rigid rotation of a stressed ring costs nothing in K_z, as in
// the continuum. With the free nodes in world coordinates, Newton's linearization sees along that
// rotation the stiffness −Σ r·(x − x_B) of the contact forces r (a node moving along its tangent
// leaves the circle), −N (R − δ) for a wheel pressed by N: negative, and the iteration diverges.
// Newton's method on z needs T = ∂Φ/∂z (velocity components × nz) and, for the equilibrium
// Tᵀ f(q) = 0 with f the generalized force (N, N·m), the reduced tangent
//   K_z = Tᵀ K T − Σ_i f_i ∂²Φ_i/∂z²,
// whose second term is the frame's geometric stiffness: with s = R_B⁻¹ (x_a − x_B) the arm in B's
// body frame and e_i B's body axes,
//   ∂x_a/∂θ_i = R_B (e_i × s),  ∂²x_a/∂θ_i∂θ_j = R_B ½ (e_i × (e_j × s) + e_j × (e_i × s)),
//   ∂²x_a/∂θ_i∂w_k = R_B (e_i × R_B,ref⁻¹ e_k)
// (the plane hub: one axis e_z, ∂²x_a/∂φ² = −R (a + w_a)). Units: q as the bodies' (m, rad); z the same.
// The floating bodies' part of Tᵀ K T is evaluated in the hub's frame. Their nodes are at
// x_a = x_B + R_rel (a + w_a), so F = R_rel F', F' the deformation gradient of the frame configuration
// X + w; the strain energy being objective, the internal force and tangent at q are those at X + w
// turned by R_rel: f_a = R_rel f'_a, K = B K' Bᵀ, B = diag(R_rel) over the nodes. With T = B T̃, T̃ is the
// identity on the w unknowns and R_relᵀ ∂x_a/∂(hub) on the hub's (a few dense columns C), and
//   Tᵀ K T = T̃ᵀ K' T̃ = Sᵀ K' S + Sᵀ K' C + Cᵀ K' S + Cᵀ K' C   (S the selection of the unknowns):
// K' itself on the w unknowns, no turning of its entries, and a few dense columns. That is why the
// stepper evaluates a finite-strain floating body at frame_positions (it costs a rotation of f per
// node): the general sparse products Tᵀ K T, with R_rel in every node's block, and their storage
// conversions took 13 % of a 68 × 10 rolling-ring run; reduce_stiffness takes 6 %. World-frame entries
// (springs; a small-strain body, whose energy is not objective) are turned entry by entry, Bᵀ K B.
#pragma once

#include "engine/dynamics.h"
#include "engine/linear_algebra/sparse_assembly.h"
#include "engine/linear_algebra/sparse_row.h"
#include "engine/world.h"

#include <Eigen/SparseCore>

#include <array>
#include <vector>

namespace csim {

using SparseRowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

class ReducedCoordinates final : public BodyFrames {
 public:
  // Throws std::invalid_argument (the caller reports it) for a component prescribed twice, a tied body
  // with a fixed component its hub's frame can move or two ties, or a tie to a body that is not a
  // rigid body. The prescriptions active at time t (PrescribedComponent::until).
  ReducedCoordinates(const World& world, double t);

  int size() const { return unknown_count_; }
  bool identity() const { return identity_; }  // nothing prescribed or tied: T = I
  // The unknown of velocity component i, or −1 (prescribed or tied).
  int unknown(int i) const { return unknown_of_[i]; }
  bool prescribed(int i) const { return prescription_of_[i] >= 0; }
  // Unknowns that belong to a rigid body carrying tied nodes (a hub): their stiffness comes only through
  // the ring, which a rigid-body mode of the ring leaves without (see quasi_static.h).
  const std::vector<int>& hub_unknowns() const { return hub_unknowns_; }

  // z ← the unknowns at q (time t, s); q becomes the base of the bodies moved by increments.
  void gather(const Vector& q, double t, Vector& z);
  void expand(const Vector& z, double t, Vector& q) const;    // q ← Φ(z, t)
  // The generalized force f (N, N·m, in velocity components) on each prescribed component, through
  // every coordinate that moves with it (a hub's spin carries its ring's nodes): ∂Φ/∂p ᵀ f, p the
  // prescribed coordinate; zero on the other components.
  void prescribed_forces(const Vector& q, const Vector& f, Vector& forces) const;
  // T at q (the floating bodies' columns depend on q, through their frame's rotation); row-major, as
  // contact rows H T are formed row by row.
  void tangent(const Vector& q, SparseRowMatrix& T) const;

  // Whether world body b rides in a hub's frame (a tied elastic body).
  bool floats(int body) const { return floating_body_of_[body] >= 0; }
  // Floating body b's positions with its hub's motion taken out, the frame configuration X + w (its
  // tied nodes at X): its internal force and tangent there are those at q in the hub's frame.
  void frame_positions(const Vector& q, int body, Vector& positions) const override;
  // f += f_frame turned to the world, B f_frame, over floating body b's velocity components.
  void add_turned_to_world(const Vector& q, int body, const Vector& f_frame, VectorRef f) const override;
  bool in_frame(int body) const override { return floats(body); }
  // K_z = Tᵀ K T − Σ f_i ∂²Φ_i/∂z² at q (f the generalized force at q), K given as triplets over
  // velocity components: the floating bodies' in their hub's frame (their tangent at frame_positions)
  // before world_from, the rest (springs) in the world frame from world_from on.
  void reduce_stiffness(const Vector& q, const Vector& f, const Triplets& K, std::size_t world_from,
                        SparseMatrix& K_z);
  // G = −Σ f_i ∂²Φ_i/∂z² alone (nz × nz); false, G untouched, when it is zero (no hub turns).
  bool geometric_stiffness(const Vector& q, const Vector& f, SparseMatrix& G) const;

 private:
  // A rigid body carrying tied nodes.
  struct Hub {
    int body = -1;
    Eigen::Matrix3d rotation_ref = Eigen::Matrix3d::Identity();  // R_B,ref
    Eigen::Vector3d centre_ref = Eigen::Vector3d::Zero();        // x_B,ref (m)
    std::vector<std::pair<int, Eigen::Vector3d>> axes;           // rotation components and their body axes
  };
  // A node of a body riding in a rigid body's frame.
  struct Floating {
    std::array<int, 3> dof{-1, -1, -1};      // velocity index of x, y, z; −1 when fixed or absent
    std::array<int, 3> position{-1, -1, -1}; // the same in q
    std::array<int, 3> unknown{-1, -1, -1};  // its w entries of z, −1 for a tied node or a fixed component
    Eigen::Vector3d arm = Eigen::Vector3d::Zero();  // a = X_a − x_B,ref (m)
    int hub = 0;                            // in hubs_
  };
  Eigen::Isometry3d hub_pose(const Hub& hub, const Vector& q) const;
  // Every hub's pose at q, in hubs_' order: computed once per call, not once per node it carries.
  std::vector<Eigen::Isometry3d> hub_poses(const Vector& q) const;
  Eigen::Vector3d node_position(const Floating& node, const Vector& q) const;  // x_a at q (m)
  // R_rel = R_B R_B,ref⁻¹, the hub's rotation since the reference, at its pose.
  Eigen::Matrix3d relative_rotation(const Hub& hub, const Eigen::Isometry3d& pose) const;
  std::vector<Eigen::Matrix3d> relative_rotations(const std::vector<Eigen::Isometry3d>& poses) const;  // per hub
  // ∂x_a/∂(hub velocity components): the node moves as the hub's material point at its place (its
  // body-frame position from the inverse of the hub's pose, inverted once per hub, not per node).
  PointJacobian hub_columns(const Floating& node, const Vector& q, const Eigen::Isometry3d& inverse_pose) const;
  static std::vector<Eigen::Isometry3d> inverses(const std::vector<Eigen::Isometry3d>& poses);
  Eigen::Vector3d node_force(const Floating& node, const Vector& f) const;
  // Throws unless the hub's frame keeps component c of the tied body's nodes where it is.
  void check_fixed_component(const Hub& hub, int c, const std::string& body_name) const;
  // G's entries (geometric_stiffness) appended to entries.
  void add_geometric_stiffness(const Vector& q, const Vector& f, Triplets& entries) const;
  // K's world-frame entries that touch floating nodes, turned to their hub's frame (Bᵀ K B), into entries.
  void add_turned_to_frame(const Vector& q, const Triplets& K, std::size_t from, Triplets& entries) const;
  // C: T̃'s hub columns (velocity components × hub_unknowns_), R_relᵀ ∂x_a/∂(hub) on floating nodes.
  void hub_frame_columns(const Vector& q, Matrix& C) const;

  const World* world_;  // a pointer, so that a stepper can rebuild its reduced coordinates
  int unknown_count_ = 0;
  bool identity_ = true;
  // Per velocity component: its unknown, its prescription, its floating node, its index in q (−1 for
  // a body moved by increments).
  std::vector<int> unknown_of_, prescription_of_, floating_of_, position_of_;
  std::vector<int> incremental_bodies_;  // bodies with velocity components that are no coordinate's rate (3D rotations)
  Vector base_;                          // their base configuration (the whole q; only their slices used)
  double base_time_ = 0.0;
  std::vector<Hub> hubs_;
  std::vector<Floating> floating_;
  std::vector<int> hub_unknowns_;
  // Per world body, its nodes' range in floating_ ([first, second)), or −1 for a body that does not float.
  std::vector<int> floating_body_of_;
  std::vector<std::pair<int, int>> floating_bodies_;
  std::vector<int> selected_;  // S: per velocity component, its unknown in T̃ (a floating node's w), or −1
  // reduce_stiffness' work space: K_z's entries come in the same order at every iterate
  SparseAssembly assembly_;
  // The frame entries (K's head, before world_from) of the last iterate: their positions, and each one's
  // slot in K_z's values (−1 off the unknowns); frame_entries_ of them head K_z's stream. While they come
  // at the same positions, their values go straight to their slots (SparseAssembly::resume): K's largest
  // part (a 68 × 10 ring's 43 520 entries) skips the unknowns' look-ups and the assembly's copy.
  std::vector<std::array<int, 2>> frame_position_;
  std::vector<int> frame_slot_;
  std::size_t frame_entries_ = 0;
  bool frame_planned_ = false;
  std::vector<double> frame_sums_;
  bool same_frame_positions(const Triplets& K, std::size_t world_from) const;
  void plan_frame(const Triplets& K, std::size_t world_from);
  Triplets turned_, geometric_;
  Matrix C_, KC_, CK_;  // C, K' C and (Cᵀ K')ᵀ
  std::vector<char> reaches_hub_row_, reaches_hub_column_;
};

}  // namespace csim
