// The linear operators of the structure, for the time-steppers: the mass M (kg, kg·m²), the tangent
// stiffness K (N/m) of the springs and of the elastic bodies, their viscous damping C (N·s/m: Rayleigh
// damping of elastic bodies), and the factored iteration matrix
//   A = M + hθ C + h²θ² K
// of the θ-method, refactored only when K, h or θ changed. Small systems (up to kDenseLimit unknowns,
// all lumped scenes) are dense, because a lumped step must cost well under a microsecond: a lumped
// World (no elastic body) keeps A⁻¹ itself (dense_inverse.h), a small elastic one A's LDLᵀ; larger ones (finite elements) are sparse and factored
// with CHOLMOD's simplicial LDLᵀ (sparse_ldlt.h), once while K and h
// stay the same (linear elastic bodies, springs on translating points), else at every step. With a
// finite-strain (hyperelastic) body, K is its tangent at the q of the last update: Moreau–Jean's Newton
// iterations refresh it at every iterate. That tangent can be indefinite (a compressed body held only
// by contacts, whose own stiffness is not in K: its sway and buckling modes), and so can A when the
// masses are small: A then gets a proximal term ε I (engine/steppers/proximal.h: from 1e-6 · max diag A
// grown tenfold until A is positive definite; the pivots D of the LDLᵀ are checked).
// Newton's residual is exact, so the term changes the iterations' path, not the converged step.
#pragma once

#include "engine/dynamics.h"
#include "engine/linear_algebra/sparse_ldlt.h"

namespace csim {

class StructuralOperators {
 public:
  static constexpr int kDenseLimit = 64;

  explicit StructuralOperators(const Dynamics& dynamics);

  // Refreshes K at q and refactors A when needed (always the first time).
  void update(const Vector& q, double h, double theta) { update_coefficients(q, h * theta, h * h * theta * theta); }
  // The same for A = M + c_C C + c_K K with the coefficients of another scheme (c_C in s, c_K in s²;
  // the generalized-α iteration matrix of generalized_alpha.h).
  void update_coefficients(const Vector& q, double damping_coefficient, double stiffness_coefficient);
  bool nonlinear() const { return nonlinear_; }  // a body's K depends on q (a finite-strain body)
  bool has_stiffness() const { return has_stiffness_; }
  bool has_damping() const { return has_damping_; }
  bool sparse() const { return sparse_; }
  int size() const { return world_.velocity_size; }  // n, the unknowns (velocity components)
  double factorization_seconds() const { return factorization_seconds_; }  // s, total
  long factorizations() const { return factorizations_; }  // how many times A was factored
  long regularizations() const { return regularizations_; }  // factorizations that needed ε I

  void solve_in_place(Vector& x) const;   // x ← A⁻¹ x
  // A dense lumped World (no elastic body) keeps A⁻¹ (dense_inverse.h): then dense_columns gives
  // G = A⁻¹ Hᵀ for Hᵀ given by its columns (n × m).
  bool explicit_inverse() const { return explicit_inverse_; }
  void dense_columns(const Matrix& Ht, Matrix& G) const;
  // A sparse finite-strain World refactors A at every Newton iterate, so A⁻¹ Hᵀ's columns are not
  // reused: its Delassus operator H A⁻¹ Hᵀ then comes from the forward substitution alone
  // (sparse_ldlt.h). H: rows × unknowns, dense storage.
  bool direct_delassus() const { return sparse_ && nonlinear_; }
  // A sparse World whose A is M alone (no stiffness, no damping) and M block diagonal by body, each block at
  // most six unknowns (rigid bodies and point masses): A⁻¹ is then applied body by body
  // (engine/contact_stage/body_block_operator.h), and the mass blocks are A's.
  bool block_diagonal() const { return block_diagonal_; }
  const SparseMatrix& mass() const { return dynamics_.mass(); }
  const World& world() const { return world_; }
  void delassus(const Matrix& H, Matrix& D) { sparse_factor_.delassus(H, D); }
  // The sparse factor of A (sparse() only), for the Delassus operator of rows kept from step to step
  // (delassus_cache.h).
  const SparseLdlt& sparse_factor() const { return sparse_factor_; }
  void apply_mass(const Vector& v, Vector& out) const;       // out = M v
  // ½ vᵀ M v (J), Dynamics::kinetic_energy's value to the bit, and Mx = M x (apply_mass's): a large M
  // read once for both (Dynamics::kinetic_energy with a second product), a diagonal M applied by its
  // diagonal (small_dense_products.h). Mx must not be x.
  double kinetic_energy(const Vector& v, const Vector& x, Vector& Mx) const;
  double kinetic_energy(const Vector& v, Vector& scratch) const;  // ½ vᵀ M v alone, the same bits
  void apply_stiffness(const Vector& v, Vector& out) const;  // out = K v
  void apply_damping(const Vector& v, Vector& out) const;    // out = C v

 private:
  const World& world_;
  const Dynamics& dynamics_;
  bool sparse_, has_stiffness_, has_damping_, nonlinear_ = false;
  bool explicit_inverse_;  // a dense lumped World: A⁻¹ kept (dense_inverse_), else dense_factor_
  bool block_diagonal_ = false;
  bool factored_ = false;
  double factored_damping_ = 0.0, factored_stiffness_ = 0.0, factorization_seconds_ = 0.0;
  long factorizations_ = 0, regularizations_ = 0;
  std::vector<double> factored_coordinates_;  // the springs' orientation coordinates A was factored at
  Matrix dense_mass_, dense_stiffness_, dense_damping_, dense_iteration_;
  // A dense linear World's springs' Jacobian columns (Dynamics::spring_jacobian_columns) where A was formed.
  std::vector<double> factored_spring_columns_;
  Matrix dense_inverse_, dense_scratch_;  // A⁻¹, and the Cholesky factor it is computed from
  // A lumped World's M, and A⁻¹, when diagonal (a point, an unsprung rigid body in space): their
  // products by the diagonal alone, the same to the bit (small_dense_products.h).
  bool mass_diagonal_ = false, inverse_diagonal_ = false;
  Vector mass_diagonal_entries_, inverse_diagonal_entries_;
  Eigen::LDLT<Matrix> dense_factor_;
  mutable Vector dense_solution_;          // solve_in_place's product (one thread per stepper, as the run)
  // M and C are Dynamics'. body_stiffness_: the bodies' K (a finite-strain body's tangent at q), dropped
  // by a sparse constant K with springs once their sum sparse_stiffness_ is formed; K is the one that
  // stiffness() names. A large FE body's K-sized matrices are thus held once here, not three times.
  SparseMatrix body_stiffness_, sparse_stiffness_;
  // CHOLMOD's LDLᵀ (sparse_ldlt.h: ordering, refactorization and sweeps, with their figures in
  // docs/solver-measurements.md, "The sparse factor"); for a nonlinear World its pivots say whether A > 0.
  SparseLdlt sparse_factor_;

  const SparseMatrix& stiffness() const { return dynamics_.has_springs() ? sparse_stiffness_ : body_stiffness_; }
  bool factored_for(const Vector& q, double damping_coefficient, double stiffness_coefficient) const;
  // A dense linear World with springs: A is kept while the springs' Jacobian columns are the same to the bit.
  bool compares_columns() const { return !sparse_ && !nonlinear_ && dynamics_.has_springs(); }
  void factor_dense(const Matrix& A);
  void factor_regularized(const SparseMatrix& A);
  template <class PositiveDefiniteWith>
  void regularize(double largest, PositiveDefiniteWith&& positive_definite_with);
};

}  // namespace csim
