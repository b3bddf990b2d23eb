// A linear World's stiffness K (N/m: its linear elastic bodies', block by block) and mass M (kg),
// applied to several vectors in one pass over both.
//
// A Moreau–Jean step of a sparse linear World ends with K q_{k+1} (its elastic energy, the next step's
// internal force), K v_{k+1} (the next step's θ h K v_k), M v_{k+1} (its kinetic energy) and, for θ ≠ ½,
// M Δv (the numerical dissipation). As separate sparse products they read K twice and M twice between
// the backward sweep of the step and the forward sweep of the next, and push the factor out of the
// cache (docs/solver-measurements.md). Here each column of K and of M is read once, for all of them.
// Each product takes the same terms in the same order as Eigen's column-major product (y_i += a_ij x_j,
// column by column), hence the same bits. Nothing is copied: K is read from the bodies, M from Dynamics.
#pragma once

#include "engine/bodies/body.h"

#include <vector>

namespace csim {

class LinearProducts {
 public:
  // A body's K (compressed, square) at its velocity offset: the World's K is their block-diagonal sum.
  // Its columns take the body's positions from position_offset in q (a body with a quaternion before
  // it moves q's offsets away from v's).
  struct StiffnessBlock {
    int offset;
    int position_offset;
    const SparseMatrix* stiffness;
  };

  LinearProducts() = default;
  // M: n × n, compressed; the blocks in increasing offset, within n. Both must outlive this.
  LinearProducts(std::vector<StiffnessBlock> K, const SparseMatrix& M);

  int size() const { return mass_ ? static_cast<int>(mass_->rows()) : -1; }

  // Kq = K q, Kv = K v, Mv = M v and, when dv is given, Mdv = M dv (each set, at size n, in v's layout;
  // q in the World's positions, the others in its velocities).
  void multiply(const Vector& q, const Vector& v, const Vector* dv, Vector& Kq, Vector& Kv, Vector& Mv,
                Vector* Mdv) const;
  // Kx = K x alone, the same to the bit as multiply's K q.
  void multiply_stiffness(const Vector& x, Vector& Kx) const;

 private:
  template <bool WithDv>
  void multiply_columns(const double* q, const double* v, const double* dv, double* Kq, double* Kv, double* Mv,
                        double* Mdv) const;

  std::vector<StiffnessBlock> stiffness_;
  const SparseMatrix* mass_ = nullptr;
};

}  // namespace csim
