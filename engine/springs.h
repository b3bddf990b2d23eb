// The World's linear springs (world.h), as the smooth dynamics sums them (dynamics.h).
//
// A spring between material points a and b (b the ground when body_b < 0) of stiffness k (N/m) has the
// elongation e = P d (m): d = (x_a − x_a,ref) − (x_b − x_b,ref), the points' relative displacement from
// the reference configuration, and P = n nᵀ along its unit direction n (I without one). It pulls a with
// F_a = −k e (N) and b with −F_a, that is the generalized force J_aᵀ F_a − J_bᵀ F_a (N, N·m), stores
// ½ k |e|² (J), and has the stiffness k Jᵀ P J, J = J_a − J_b (first order: no geometric term of ends
// that turn).
//
// Everything a step asks of them at one q — the ends' Jacobians, the elongations, the generalized
// forces — comes from one evaluation, kept for the next question at the same q (the same bits): a
// Moreau–Jean step's energy at q_{k+1}, the next step's forces there and its check of the iteration
// matrix share it.
#pragma once

#include "engine/world.h"

#include <array>
#include <vector>

namespace csim {

class Springs {
 public:
  explicit Springs(const World& world);

  bool empty() const { return world_.springs.empty(); }

  void add_forces(const Vector& q, Vector& f) const;        // f += Σ J_aᵀ F_a − J_bᵀ F_a
  void add_energy(const Vector& q, double& energy) const;  // energy += ½ k |e|², spring by spring (J)
  // K = Σ k Jᵀ P J at q, as triplets (one per nonzero product) or dense (set, the springs only).
  void add_stiffness(const Vector& q, Triplets& K) const;
  void stiffness(const Vector& q, Matrix& K) const;
  // out += K v at q, spring by spring: k Jᵀ P (J v) (N).
  void add_stiffness_product(const Vector& q, const Vector& v, Vector& out) const;
  // The ends' Jacobian columns at q, spring by spring, end a then end b (m per unit velocity
  // component): K is a function of them alone, so that equal columns mean the same K to the bit.
  void jacobian_columns(const Vector& q, std::vector<double>& columns) const;
  // Whether those at q are `columns` to the bit (compared where they are, not copied out).
  bool same_jacobian_columns(const Vector& q, const std::vector<double>& columns) const;
  // The indices in q that K depends on: the orientation coordinates of the bodies with a spring
  // attached off their origin, sorted (none: K is constant).
  const std::vector<int>& stiffness_coordinates() const { return stiffness_coordinates_; }

 private:
  // One spring end: its body's velocity offset, its point's Jacobian (count 0 for the ground) and the
  // spring's generalized force on it, force[k] = ±(column k · F_a) (N or N·m; − on end b).
  struct End {
    int offset = 0;
    PointJacobian jacobian;
    std::array<double, 9> force;
  };
  // What the springs are at one q, sized once; a memo of a pure function, one thread per run.
  struct Evaluation {
    Vector positions;                          // that q (empty before the first evaluation)
    std::vector<End> ends;                     // 2 per spring: a, then b
    std::vector<Eigen::Vector3d> elongations;  // e = P d per spring (m)
  };
  const Evaluation& at(const Vector& q) const;

  const World& world_;
  std::vector<Eigen::Vector3d> reference_points_a_, reference_points_b_;  // world points at q_ref (m)
  std::vector<Eigen::Matrix3d> projectors_;                               // each spring's P
  std::vector<int> stiffness_coordinates_;
  mutable Evaluation kept_;
};

}  // namespace csim
