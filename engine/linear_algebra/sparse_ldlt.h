// The sparse LDLᵀ factor of a symmetric matrix A, P A Pᵀ = L D Lᵀ (CHOLMOD's simplicial LDLᵀ from
// Debian's SuiteSparse, with the cheaper of its AMD and METIS orderings), with what the steppers ask of
// it: whether A is positive definite, solves, and the Delassus operator of contact rows. One class for
// the linear iteration matrix of finite elements, the finite-strain tangent and the quasi-static
// stiffness; CHOLMOD's headers stay in the .cpp.
//
// Refactorizations. A pattern's first factorization is CHOLMOD's; the later ones of the same pattern
// (a Newton iteration's tangents) are numerically supernodal (supernodal_ldlt.h) into CHOLMOD's storage,
// whose solves then read them: the same L and D at round-off, in a fraction of the up-looking
// factorization's time. A matrix that is not positive definite is factored again by CHOLMOD, so that
// the factor left is its complete LDLᵀ, as before.
//
// Solves. A whole solve (solve, solve_in_place) is CHOLMOD's. The two halves of a solve around a contact
// solve (forward_substitute, back_substitute, and solve_free, solve_with_reactions: a linear step's, the
// quasi-static stepper's, a Newton step's impulses) are swept by supernodes over CHOLMOD's storage
// (supernodal_sweeps.h): a linear step streams a large L once in each, and read by supernodes it is 8
// bytes an entry instead of 12 (docs/solver-measurements.md, ninth round). The two agree at round-off.
//
// Symbolic analysis. The ordering and the elimination tree depend on A's pattern only, which a Newton
// iteration's tangent mostly keeps (a node contact's rows sit in its node's block, already there; rows
// that couple nodes not yet coupled, such as a smoothed surface's, change it); they are recomputed
// when the pattern changes, not at every factorization, with the map that writes A's lower triangle
// into triu(P A Pᵀ), the matrix CHOLMOD's factorization reads (no transpose at each factorization).
//
// Delassus operator W = H A⁻¹ Hᵀ of rows H (m × n, each row touching a few unknowns), without A⁻¹ Hᵀ.
// For one row, Y = L⁻¹ P hᵀ: a column of P Hᵀ has a handful of nonzeros, and the forward substitution
// fills only the union of their paths to the root of the elimination tree (Gilbert & Peierls 1988;
// Davis, Direct Methods for Sparse Linear Systems, 2006, §3.2), reading only L's columns on it, so that
// a column of Y costs a small part of a solve (which reads all of L twice) and holds a small part of the
// n entries of A⁻¹ hᵀ. forward gives one such sparse column (kept by the caller, e.g. per contact;
// delassus_cache.h), delassus_entry one entry of W from two of them.
// delassus forms all of W for dense rows H through the unknowns S that the rows touch:
//   G = E_Sᵀ A⁻¹ E_S = Yᵀ D⁻¹ Y,  Y = L⁻¹ P E_S (one forward column per unknown),   W = H_S G H_Sᵀ,
// and keeps G while the factor and S stay the same: the quasi-static stepper's modified Newton iterates
// solve with one factor (kept_factor.h) and their contacts touch the same nodes, while their rows turn
// with a hub's frame (reduced_coordinates.h), so that such an iterate's W costs H_S G H_Sᵀ alone. Node
// contacts' rows share their node's unknowns (d rows, d unknowns), so |S| is about m and G costs about
// what Y of the rows would.
#pragma once

#include "engine/bodies/body.h"
#include "engine/linear_algebra/supernodal_ldlt.h"
#include "engine/linear_algebra/supernodal_sweeps.h"

#include <memory>
#include <vector>

namespace csim {

class SparseLdlt {
 public:
  // A sparse column of Y = L⁻¹ P hᵀ: its nonzero rows (in the factor's order, ascending) and values.
  struct ForwardColumn {
    std::vector<int> index;
    std::vector<double> value;
  };

  SparseLdlt();
  ~SparseLdlt();
  SparseLdlt(const SparseLdlt&) = delete;
  SparseLdlt& operator=(const SparseLdlt&) = delete;

  // Factors A (compressed or not; its lower triangle is read); true when the factorization succeeded
  // with every pivot of D positive.
  bool factor_positive_definite(const SparseMatrix& A);
  // The unknowns (in A's numbering) whose pivot in the last factorization is at most tolerance × their
  // diagonal entry A_jj (diagonal: A's diagonal, in A's numbering): D_j is what A_jj keeps once the
  // unknowns eliminated before j have taken their share, so a small ratio is a direction that A holds by
  // that fraction of its own stiffness or not at all (a ratio at round-off, of either sign: a mechanism
  // the arithmetic cannot tell from a soft spring). After a factorization stopped by a zero pivot, that
  // pivot's unknown alone (the later pivots are not known). Scale-free: the same unknowns for c A, c > 0.
  std::vector<int> small_pivots(const Vector& diagonal, double tolerance) const;
  Vector solve(const Vector& b) const;  // A⁻¹ b
  void solve_in_place(Vector& x) const;  // x ← A⁻¹ x
  // W (m × m) ← H A⁻¹ Hᵀ; H is m × n, in dense storage. With the last G when neither the factor nor the
  // unknowns H touches changed since (see above).
  void delassus(const Matrix& H, Matrix& W);
  // The solve of a contact problem in two halves around its contact solve, after delassus(H, W) with the
  // same H and factor: solve_free sets Hx = H A⁻¹ f and keeps w = L⁻¹ P f; solve_with_reactions then sets
  // x = A⁻¹ (f + Hᵀ r) = Pᵀ L⁻ᵀ D⁻¹ (w + Y_S H_Sᵀ r) from the inverse block's forward columns Y_S: one
  // forward and one backward substitution for the pair, where A⁻¹ f and A⁻¹ Hᵀ r take two of each.
  void solve_free(const Vector& f, Vector& Hx);
  void solve_with_reactions(const Vector& r, Vector& x);
  // The first half of a solve: w ← L⁻¹ P f and z ← D⁻¹ w (the factor's order; w is not f), so that a row's
  // h A⁻¹ f = dot(y_h, z) from its forward column y_h, and A⁻¹ (f + Hᵀ r) = back_substitute(w + Σ r_a y_a).
  void forward_substitute(const Vector& f, Vector& w, Vector& z) const;
  // y ← L⁻¹ P hᵀ for the row h = Σ_k value[k] e_{index[k]}ᵀ (count entries, distinct indices).
  void forward(const int* index, const double* value, int count, ForwardColumn& y) const;
  // y_aᵀ D⁻¹ y_b: the entry of W of the two rows whose forward columns these are.
  double delassus_entry(const ForwardColumn& a, const ForwardColumn& b) const;
  // x ← Pᵀ L⁻ᵀ D⁻¹ z, z in the factor's order (Σ r_a y_a of forward columns): the second half of a solve,
  // so that A⁻¹ Hᵀ r costs a backward substitution once Y's columns are known.
  void back_substitute(const Vector& z, Vector& x) const;
  // x(i) ← y(i) / D_i on y's rows (x dense, in the factor's order): then y_bᵀ D⁻¹ y = dot(y_b, x).
  void scatter_scaled(const ForwardColumn& y, Vector& x) const;
  static double dot(const ForwardColumn& y, const Vector& x);
  static void add_scaled(double a, const ForwardColumn& y, Vector& x);  // x(i) += a y(i) on y's rows
  // Frees what only a refactorization reads (A's pattern and its map into triu(P A Pᵀ), about 20 bytes
  // an entry of A's lower triangle): for a matrix factored once. A later factorization analyses again.
  void release_pattern();
  int size() const;                            // n
  long analyses() const { return analyses_; }  // symbolic analyses so far
  long factorizations() const { return factorizations_; }
  long kept_delassus() const { return kept_delassus_; }  // delassus calls that took the last G
  long supernodal_factorizations() const { return supernodal_factorizations_; }  // of factorizations()
  double factor_nonzeros() const;              // entries of L, its diagonal (D) included

 private:
  struct Cholmod;
  std::unique_ptr<Cholmod> cholmod_;
  std::vector<int> outer_, inner_;  // the pattern the analysis was made for
  long analyses_ = 0, factorizations_ = 0, kept_delassus_ = 0;
  // Refactorizations of a pattern go through supernodal_ (supernodal_ldlt.h) into the storage of
  // CHOLMOD's last complete factor of it, whose row indices they keep: ready once its pattern is checked.
  SupernodalLdlt supernodal_;
  bool cholmod_complete_ = false, supernodal_ready_ = false;
  // The forward and backward sweeps by supernodes (supernodal_sweeps.h), of the pattern CHOLMOD's last
  // complete factorization left in its storage (a supernodal refactorization keeps it).
  mutable SupernodalSweeps sweeps_;
  mutable bool sweeps_ready_ = false;
  const SupernodalSweeps& sweeps() const;
  long supernodal_factorizations_ = 0;
  // The elimination tree (parent of each column of L, −1 at a root) and the diagonal D, read from L
  // after each factorization when forward asks.
  mutable std::vector<int> parent_;
  mutable Vector pivots_;
  mutable bool tree_ready_ = false;
  mutable std::vector<int> mark_, reach_;  // forward's work space: a visit mark by column, the reach
  mutable Vector work_;                    // forward's dense work vector, zero between calls
  Matrix Y_, compact_;                     // inverse_block's work space (Y_ zero between calls)
  std::vector<ForwardColumn> columns_;     // Y's columns
  std::vector<int> rows_, row_start_, row_columns_, fill_;
  // G = E_Sᵀ A⁻¹ E_S for the unknowns S (ascending), made with the factorization gram_factorization_
  // (−1: none); touched_ the unknowns of the rows at hand.
  std::vector<int> unknowns_, touched_;
  Matrix gram_;
  long gram_factorization_ = -1;
  Matrix rows_on_unknowns_, rows_times_block_;  // H_S and H_S G
  Vector free_forward_, block_values_;         // solve_free's w = L⁻¹ P f, and E_Sᵀ A⁻¹ f or H_Sᵀ r
  void analyse(const SparseMatrix& A);  // the ordering and symbolic factor of A's pattern
  void prepare_tree() const;
  void forward_sweep(const Vector& f, Vector& w) const;  // w ← L⁻¹ P f
  void inverse_block();  // gram_ for unknowns_
};

}  // namespace csim
