// The iteration matrix A of a stepper as its contact stage sees it (the role of Drake's LinearOperator
// in multibody/contact_solvers, of Siconos' OSI W / Winverse in LinearOSNS): for the rows H of a contact
// problem, the Delassus operator W = H A⁻¹ Hᵀ and the velocity response A⁻¹ Hᵀ r to impulses r. How A⁻¹
// is stored and applied sits behind it; the stage and the stepper never ask which:
//   - a lumped World keeps A⁻¹ itself (dense_inverse.h): G = A⁻¹ Hᵀ and W = H G by small products;
//   - a small elastic World keeps A's dense LDLᵀ: a column A⁻¹ hᵀ a row, W(a, b) = h_a · A⁻¹ h_bᵀ;
//   - a sparse World with a constant A (linear finite elements) keeps each row's forward column
//     y = L⁻¹ P hᵀ by its identity while A stays (delassus_cache.h), W(a, b) = y_aᵀ D⁻¹ y_b, and
//     A⁻¹ Hᵀ r = Pᵀ L⁻ᵀ D⁻¹ (Σ r_a y_a), one backward substitution;
//   - a sparse World refactored at every Newton iterate (finite strain) takes W from the forward
//     substitution alone (SparseLdlt::delassus) and A⁻¹ (Hᵀ r) by one solve.
// A is the one StructuralOperators factors (structural_operators.h: M + c_C C + c_K K); a stepper whose
// contact response is another operator of A (generalized_alpha.h) supplies its own.
#pragma once

#include "contact/friction_contact_problem.h"
#include "engine/contact_stage/problem_rows.h"

#include <memory>

namespace csim {

class StructuralOperators;

// How the contact stage stores W (scene key contact_solver.storage): sparse by blocks where the operator
// finds it pays (automatic), always dense, or sparse whenever the operator can form it so.
enum class DelassusChoice { automatic, dense, sparse };

class IterationOperator {
 public:
  virtual ~IterationOperator() = default;
  // W (m × m, symmetric) ← H A⁻¹ Hᵀ for these rows (A as factored now); keeps what add_response needs.
  virtual void delassus(const ProblemRows& rows, Matrix& W) = 0;
  // The same W stored sparse by whole blocks (contact/friction_contact_problem.h), when this operator
  // finds that it pays (many contacts between bodies that A does not couple) or, `forced`, whenever it
  // can form it so; false otherwise, and the stage then asks delassus(). add_response answers for the
  // rows of either.
  virtual bool sparse_delassus(const ProblemRows&, SparseDelassus&, bool /*forced*/) { return false; }
  // When it pays, for every operator that can store W so (`automatic`): at least kSparseRows rows, and no
  // unknown (or factor row) reached by more than kSparseDensity of the rows' blocks (block_pattern.h).
  static constexpr int kSparseRows = 48;
  static constexpr double kSparseDensity = 0.25;
  // W's body-block factors (contact/friction_contact_problem.h) of the rows of the last sparse_delassus(),
  // for an operator of an A block diagonal by body (body_block_operator.h); false otherwise.
  virtual bool body_blocks(BodyBlockDelassus&) const { return false; }
  // v += A⁻¹ Hᵀ r, H the rows of the last delassus() (r: one impulse a row, N·s; v in m/s).
  virtual void add_response(const ProblemRows& rows, const Vector& r, Vector& v) = 0;
  // u = H v, H the rows of the last delassus() (an operator that holds H dense applies it so).
  virtual void apply_rows(const ProblemRows& rows, const Vector& v, Vector& u) const {
    u.resize(rows.size());
    for (int a = 0; a < rows.size(); ++a) u(a) = rows.dot(a, v);
  }
  // Called when the stage has gathered new rows, before W: an operator that holds the rows in its own
  // coordinates (the quasi-static stepper's, over its reduced unknowns) forms them here.
  virtual void gather(const ProblemRows&) {}
};

// The operator of A as `operators` stores it (read at each call: A may be refactored between steps).
std::unique_ptr<IterationOperator> make_iteration_operator(StructuralOperators& operators);

}  // namespace csim
