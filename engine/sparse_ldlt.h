// The sparse LDLᵀ factor of a symmetric matrix A (A = Pᵀ L D Lᵀ P, Eigen's SimplicialLDLT with its AMD
// ordering), with what a Newton stepper asks of it: whether A is positive definite, solves, and the
// Delassus operator of contact rows.
//
// Symbolic analysis. The ordering and the elimination tree depend on A's pattern only, which a Newton
// iteration's tangent mostly keeps (a node contact's rows sit in its node's block, already there; rows
// that couple nodes not yet coupled, such as a smoothed surface's, change it); they are recomputed
// when the pattern changes, not at every factorization (2 analyses in a 68 × 10 rolling-ring run, where
// there were 1613).
//
// Delassus operator W = H A⁻¹ Hᵀ of rows H (m × n, each row touching a few unknowns), without A⁻¹ Hᵀ:
//   Y = L⁻¹ P Hᵀ,   W = Yᵀ D⁻¹ Y.
// Eigen's forward substitution with a column-major L skips the zero entries of its right-hand side,
// and P Hᵀ's columns have a handful of nonzeros whose elimination-tree paths fill part of each column
// of Y; the backward substitution that a full solve adds reads every entry of L for every column. The
// product Yᵀ D⁻¹ Y takes each row of Y's nonzeros only (delassus).
#pragma once

#include "engine/bodies/body.h"

#include <Eigen/SparseCholesky>
#include <vector>

namespace csim {

class SparseLdlt {
 public:
  // Factors A (compressed); true when the factorization succeeded with every pivot of D positive.
  bool factor_positive_definite(const SparseMatrix& A);
  Vector solve(const Vector& b) const { return factor_.solve(b); }  // A⁻¹ b
  // W (m × m) ← H A⁻¹ Hᵀ; H is m × n, in dense storage.
  void delassus(const Matrix& H, Matrix& W);
  long analyses() const { return analyses_; }  // symbolic analyses so far

 private:
  Eigen::SimplicialLDLT<SparseMatrix> factor_;
  std::vector<int> outer_, inner_;  // the pattern factor_ was analysed for
  long analyses_ = 0;
  Matrix Y_, compact_;              // delassus' work space
  std::vector<int> rows_, row_start_, row_columns_, fill_;
};

}  // namespace csim
