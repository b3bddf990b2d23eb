// The sparse LDLᵀ factor of a symmetric matrix A, P A Pᵀ = L D Lᵀ (CHOLMOD's simplicial LDLᵀ from
// Debian's SuiteSparse, with the cheaper of its AMD and METIS orderings), with what the steppers ask of
// it: whether A is positive definite, solves, and the Delassus operator of contact rows. One class for
// the linear iteration matrix of finite elements, the finite-strain tangent and the quasi-static
// stiffness; CHOLMOD's headers stay in sparse_ldlt_storage.h, read by sparse_ldlt*.cpp alone.
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
// bytes an entry instead of 12 (docs/solver-measurements.md). The two agree at round-off.
//
// CHOLMOD's factor storage. The refactorization, the sweeps, forward and the pivots read (and the
// refactorization writes) the arrays of CHOLMOD's factor directly, in the layout that
// cholmod_layout_supported below checks once per CHOLMOD factorization. When it does not hold, or when
// the factor is made with Kernels::cholmod or Kernels::cholmod_ll, every operation goes through
// CHOLMOD's own routines on the same factor, with the same results at round-off: cholmod_factorize_p for
// every factorization, cholmod_solve2 for the halves (CHOLMOD_L; CHOLMOD_DLt) and for the pivots
// (CHOLMOD_D of a vector of ones), cholmod_solve2 with a sparse right-hand side (Bset, Xset) for forward.
// With an LLᵀ factor (CHOLMOD's supernodal one, or Kernels::cholmod_ll) the forward columns are D^-½
// times those of LDLᵀ and the pivots are 1, which every product of them here (W, the two halves) takes
// into account: only the ForwardColumn values themselves differ, and they are read through this class.
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

struct cholmod_factor_struct;  // CHOLMOD's cholmod_factor (cholmod_core.h), kept out of this header

namespace csim {

// Whether our kernels may read and write this CHOLMOD factor's arrays directly, as SparseLdlt's
// refactorization (supernodal_ldlt.h), sweeps (supernodal_sweeps.h), forward columns and pivots do.
// The layout they assume, each item checked here:
//  - CHOLMOD 3.x to 5.x, the library's main version that of the header it was compiled against
//    (Debian bookworm: SuiteSparse 5.12, CHOLMOD 3.0.14; the simplicial layout below is the one
//    cholmod_core.h of 3.x and cholmod.h of 4.x and 5.x document);
//  - numeric (xtype CHOLMOD_REAL, dtype CHOLMOD_DOUBLE: x holds doubles, no z), int indices (itype
//    CHOLMOD_INT: p, i, nz are int arrays);
//  - simplicial (is_super false: p, i, nz, x hold L by columns) LDLᵀ (is_ll false: the first entry of
//    column j is D_j, in place of L's unit diagonal);
//  - the natural ordering (ordering CHOLMOD_NATURAL): the factor is of triu(P A Pᵀ), P SparseLdlt's own;
//  - column j's first row index is j (i[p[j]] == j), for every j (n reads).
// Not assumed: packed or monotonic columns (columns are read at p[j], nz[j] entries); rows sorted within
// a column (the refactorization checks the whole pattern before it writes, SupernodalLdlt::matches, and
// the sweeps' supernodes compare the rows they join).
bool cholmod_layout_supported(const cholmod_factor_struct& factor);

class SparseLdlt {
 public:
  // Which code reads the factor: ours where cholmod_layout_supported (the default), or CHOLMOD's
  // routines only, on its simplicial LDLᵀ (cholmod) or on that factor turned into LLᵀ by CHOLMOD
  // (cholmod_ll: L D^½, a layout the check refuses): the fallback, chosen here for tests and benchmarks.
  enum class Kernels { ours_where_supported, cholmod, cholmod_ll };

  // A sparse column of Y = L⁻¹ P hᵀ: its nonzero rows (in the factor's order, ascending) and values.
  struct ForwardColumn {
    std::vector<int> index;
    std::vector<double> value;
  };

  SparseLdlt();
  explicit SparseLdlt(Kernels kernels);
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
  // D, in the factor's order (ones for an LLᵀ factor, see above): y_aᵀ D⁻¹ y_b = Σ_i y_a(i) y_b(i) / D_i
  // over the rows i of both columns, as delassus_entry sums it (block_gram.h sums whole blocks so).
  const Vector& pivots() const;
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
  // Whether the last CHOLMOD factorization left a factor our kernels read (see above); false before one.
  bool reads_factor_storage() const { return ours_; }
  int size() const;                            // n
  long analyses() const { return analyses_; }  // symbolic analyses so far
  long factorizations() const { return factorizations_; }
  long kept_delassus() const { return kept_delassus_; }  // delassus calls that took the last G
  long supernodal_factorizations() const { return supernodal_factorizations_; }  // of factorizations()
  double factor_nonzeros() const;              // entries of L, its diagonal (D) included

 private:
  struct Cholmod;
  std::unique_ptr<Cholmod> cholmod_;
  Kernels kernels_ = Kernels::ours_where_supported;
  bool ours_ = false;  // our kernels read the factor: the check of the last CHOLMOD factorization
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
  mutable std::vector<int> mark_, reach_, merged_;  // forward's work space: a visit mark by column, the reach
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
  // CHOLMOD's routines where the layout is not ours to read (see above).
  void forward_by_cholmod(const int* index, const double* value, int count, ForwardColumn& y) const;
  void solve_by_cholmod(int system, double* x) const;  // x ← the solution of CHOLMOD's system at x
  void cholmod_pivots(Vector& D, bool of_ldlt) const;  // D (see sparse_ldlt_cholmod.cpp)
  void forward_sweep(const Vector& f, Vector& w) const;  // w ← L⁻¹ P f
  void inverse_block();  // gram_ for unknowns_
};

}  // namespace csim
