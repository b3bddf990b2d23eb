// Generalized forces of a World in its velocity coordinates:
//   external(t)      loads λ(t)·F at their points and gravity m·g, as Jᵀ·F (N, N·m);
//   spring_forces(q) the linear springs of world.h, and their tangent stiffness K = Σ k Jᵀ P J (N/m),
//                    without the geometric term of rotating attachment points (first order);
//   body internal forces −K u of the elastic (finite-element) bodies, whose K is constant;
//   elastic_energy(q) ½ Σ k |P d|² + Σ ½ uᵀK u over the elastic bodies (J).
// Evaluated with no allocation once the work buffers are sized.
#pragma once

#include "engine/world.h"

namespace csim {

class ForceModel {
 public:
  explicit ForceModel(const World& world);

  void external(const Vector& q, double t, Vector& f) const;
  void add_spring_forces(const Vector& q, Vector& f) const;
  void spring_stiffness(const Vector& q, Matrix& K) const;
  void add_spring_stiffness(const Vector& q, Triplets& K) const;  // the same, for sparse systems
  void add_body_internal_forces(const Vector& q, Vector& f) const;
  bool has_elastic_bodies() const { return has_elastic_bodies_; }
  double elastic_energy(const Vector& q) const;

  // True when K does not depend on q (springs only on translating points), so that the iteration
  // matrix can be factored once.
  bool constant_stiffness() const { return constant_stiffness_; }
  bool has_springs() const { return !world_.springs.empty(); }

 private:
  // Relative displacement d of a spring's two points from the reference configuration (m).
  Eigen::Vector3d spring_displacement(const Spring& s, const Vector& q) const;

  const World& world_;
  std::vector<Eigen::Vector3d> reference_points_a_, reference_points_b_;  // world points at q_ref
  bool constant_stiffness_ = true;
  bool has_elastic_bodies_ = false;
};

}  // namespace csim
