// A⁻¹ of an iteration matrix that is block diagonal by body (StructuralOperators::block_diagonal: rigid
// bodies and point masses, A = M, no spring, damping or elastic body coupling two bodies), applied body by
// body as sequential-impulse solvers do. Each body's block is factored once, A_b = L_b L_bᵀ, and each
// contact's rows on each of its two bodies are scaled, K_cb = H_cb L_b⁻ᵀ (contact/friction_contact_problem.h,
// BodyBlockDelassus), so that
//   W_cd = Σ_{b moved by both} K_cb K_dbᵀ,   A⁻¹ Hᵀ r = L⁻ᵀ w,   w_b = Σ_c K_cbᵀ r_c,
// no forward substitution and no A-sized work per row (a sparse World's forward columns, forward_columns.h,
// cost a pile's detection its candidates' columns). The blocks are summed in ascending body order, each
// entry Σ_k K_cb(i, k) K_db(j, k) in ascending k, so that W is symmetric to the bit. Equality and tie rows
// (dense) take their columns A⁻¹ hᵀ body by body and are stored dense, as every operator stores them.
// In two halves (two_halves_operator.h) the free solve is A⁻¹ f whole, body by body, and a candidate's
// free dot h · A⁻¹ f. The sparse W (by whole blocks, where it pays: IterationOperator::kSparseRows and a body reached by at
// most kSparseDensity of the contacts) comes with its factors, which the contact solver sweeps through
// (contact/sparse_pgs.h).
#pragma once

#include "engine/contact_stage/two_halves_operator.h"

#include <vector>

namespace csim {

class BodyBlockOperator final : public TwoHalvesOperator {
 public:
  explicit BodyBlockOperator(const StructuralOperators& operators);

  void delassus(const ProblemRows& rows, Matrix& W) override;
  bool sparse_delassus(const ProblemRows& rows, SparseDelassus& W, bool forced) override;
  bool body_blocks(BodyBlockDelassus& blocks) const override;
  void add_response(const ProblemRows& rows, const Vector& r, Vector& v) override;

  // Two halves (two_halves_operator.h): A⁻¹ f whole, the candidates' dots with it.
  void forward_half(const Vector& f) override;
  void gather_candidates(const std::vector<ActiveContact>& candidates, const std::vector<SparseRow>& rows,
                         int dimension, const Matrix* equalities) override;
  double free_dot(int c) const override { return candidate_dots_[c]; }
  void free_velocity(const Vector& v_k, Vector& v) const override { v = v_k + free_change_; }
  void velocity(const ProblemRows& rows, const Vector& r, const Vector& v_k, Vector& v) override;

 private:
  static constexpr int kBody = BodyBlockDelassus::kBodySize;
  using BodyMatrix = Eigen::Matrix<double, kBody, kBody>;
  struct BodyFactor {
    int offset = 0, size = 0;  // the body's unknowns [offset, offset + size) in v
    bool diagonal = false;     // L⁻ᵀ diagonal (a sphere, a point): K by scaling
    BodyMatrix inverse_factor_transpose = BodyMatrix::Zero();  // L_b⁻ᵀ, padded with zeros
  };
  // factors_ ← the contacts' scaled rows (each contact's bodies in ascending order).
  void scale_rows(const ProblemRows& rows);
  // W_cd (D × D, by rows into out) of two contacts, zero when they share no body.
  template <int D>
  void block(int c, int d, double* out) const;
  void apply_inverse(Vector& x) const;  // x ← A⁻¹ x, body by body

  int dimension_ = 3;
  std::vector<BodyFactor> bodies_;
  std::vector<int> body_of_;  // each unknown's body (−1: none)
  BodyBlockDelassus factors_;
  std::vector<std::vector<int>> contacts_of_;  // each body's contacts, ascending (sparse_delassus)
  std::vector<int> neighbours_;
  std::vector<Vector> equality_columns_;  // A⁻¹ hᵀ of the equality and tie rows of the last delassus()
  Vector w_;
  Vector free_change_;                  // A⁻¹ f of the last forward_half
  std::vector<double> candidate_dots_;  // the candidates' rows' and the equalities' h A⁻¹ f
};

}  // namespace csim
