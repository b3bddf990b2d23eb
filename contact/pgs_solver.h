// Projected Gauss–Seidel (non-smooth Gauss–Seidel) on the Delassus operator, with an exact local
// solve per contact (coulomb_local.h) and an exact block solve of the bilateral rows.
//
// Two paths, by the problem's storage: dense W (what follows) and sparse W (sparse_pgs.h: sweeps in
// O(stored entries), a sparse Newton polish whose work is bounded by the sweeps', equalities refused).
// A dense-stored W that is large and mostly zero blocks is routed to the sparse path on a block-sparse
// copy (PgsParameters::route_sparse).
//
// One sweep visits contacts in row order, solving each contact's local problem with the others'
// impulses frozen (relaxed by omega).
//
// Equality rows are condensed out before the sweeps: r_e = −W_ee⁺ (q_e + W_ec r_c) is exact for any
// contact impulses, so Gauss–Seidel runs on the contacts' Schur complement W_cc − W_ce W_ee⁺ W_ec, and
// r_e is recovered at the end (one step of refinement). Alternating between contacts and the equality
// block instead contracts by W_ce W_ee⁻¹ W_ec / W_cc a sweep, about 1 − 1e-5 for a light ring tied to a
// hub (W_cc 1e7, condensed 270: the 3D Moreau–Jean ring on 68 × 10 ended at 2.7e-5 after 20000 sweeps,
// and converges in 67 condensed). Condensed entries at round-off of the full ones are set to zero
// (equality_condensation.cpp). Convergence is decided on the full problem's residual at every test of
// the iteration, the polish's candidates alone being compared on the condensed one: the condensed
// residual weighs each contact's r_c − local_c(r) by its condensed W_cc, and so cannot see an impulse
// outside its cone along a zero column (a direction the ties hold), which the full W_cc weighs. The
// full residual's floor is about 1e-16 · W_cc / (condensed W): the ties' cancellation. A test at which
// the condensed residual is at tolerance and the full one above it and no lower than at the previous
// such test ends the solve, unconverged: more sweeps would not lower it.
//
// Convergence (Siconos-style: cheap test first, full residual to confirm):
//   cheap   : ‖Δr‖ of a sweep, scaled to velocity units by the Delassus diagonal, relative to
//             max(‖b‖, ‖W r‖);
//   full    : the fixed-point residual of the whole law, e = Σ_c ‖W_cc (r_c − local_c(r))‖² + ‖u_eq‖²,
//             where local_c(r) is the exact local solution of contact c with all other impulses at r;
//             it includes the friction part, not only the normal one. residual = sqrt(e) relative to
//             max(‖b‖, ‖W r‖, 1e-300).
//   converged when the full residual ≤ tolerance. Non-finite local results are rejected (the previous
//   impulse is kept) and counted.
// Polish: after 20 sweeps without convergence, then every 200, and at the end (unless the last polish
// came after the last sweep: never two polishes without a sweep between), the iterate is
// finished by direct methods, each result kept only when its full residual is smaller. On the dense
// path a scheduled polish is skipped while the sweeps, at the rate of their last ten increments,
// would reach the tolerance within 10 more sweeps, and tried again 20 sweeps later (pgs_solver.cpp);
// the sparse path's rule is its own (sparse_pgs.h). The polish:
//   1. an active-set iteration: the statuses of the iterate (open, stick, slip with its current
//      direction) turn the law into a square linear system solved directly (partial-pivot LU with a
//      step of refinement; where the system is singular, as a hyperstatic contact set's stick rows
//      are, the proximal point iteration on it), the statuses are corrected from the solution and the
//      solve repeated (8 passes at most); then the same from "every closed contact in stick";
//   2. a semismooth Newton method on the Alart–Curnier equations (alart_curnier.h), which also finds
//      slip directions in 3D, with two scalings of its augmentation parameter (on a singular
//      Jacobian, the proximal step (J + δ I) s = −F).
// No full pivoting anywhere. The polish's work is bounded (PgsParameters::polish_budget): each of its
// factorizations is refused when it would exceed the budget, and the polish then stops there.
// The pieces of the dense path are listed in dense_pgs.h.
// It rescues problems whose Delassus mixes very different scales, on which Gauss–Seidel stalls: a body
// held by weak springs (SSNV503: 20000 sweeps and 1e-8 before, 20 sweeps and 1e-9 now), a rigid body
// on two or four points of a stiff elastic one (box-on-block: no convergence in 2000 sweeps before).
//
// W need not be symmetric: the law is u = W r + b row by row, so the local problem of contact c is row
// block c of W (its diagonal block W_cc as stored, the coupling from its rows), the residual that
// decides convergence is formed from W's rows, and so is the polish (its linear systems and Newton's
// Jacobian are rows of W). Every Delassus operator the steppers form is symmetric to the bit; a W that
// is not (a problem from elsewhere, e.g. FCLib's, with a relative skew of 1e-7 to 7e-4) is read through
// its transpose, copied once per solve (m² doubles, kept by the solver). A W symmetric to round-off
// (every |W_ij − W_ji| ≤ 16 ε max_i |W_ii|, dense_pgs.h: Siconos' problems formed as J M⁻¹ Jᵀ, skew
// 1e-17 to 2e-16) is first swept on its own columns, without the copy, every convergence test made
// on W's own rows (W r formed by columns); if those sweeps settle on their own problem's solution while
// W's residual stays above the tolerance, or run out of sweeps, the solve goes on from their iterate
// through the copy (pgs_solver.cpp). On problems without equality rows only: with them, W is
// read through the copy unless symmetric to the bit. With equality rows, an unsymmetric W_ee is
// factored by a complete orthogonal decomposition instead of the LDLT.
//
// Details of this implementation:
//   - W's rows are read as contiguous columns: W's own when W is symmetric to the bit, Wᵀ's otherwise
//     (first W's own when W is symmetric to round-off, above);
//   - omega relaxes the contact impulses only; with omega > 1 a relaxed impulse is pulled back into its
//     cone (r_n ≥ 0, r_t scaled radially); the equality block is always solved exactly;
//   - right after a sweep, the contacts after the last impulse that moved (and that one, when it is
//     its own local solution) have a zero term in the full residual, which is then not recomputed:
//     they see the frozen velocity they were solved with (a sweep that moved nothing skips them all);
//   - a warm start with NaN/inf entries is discarded like one of the wrong size;
//   - status: open if r_n ≤ 0, stick if the elliptic radius of r_t is below (1 − 1e-9) r_n, slip
//     otherwise (a frictionless closed contact is slip);
//   - an inconsistent problem (sizes, dimension) throws std::invalid_argument;
//   - no heap allocation without equality rows once the solver has seen the problem's size (an
//     unsymmetric W's transpose is the solver's), except in a routed solve (route_sparse): it builds
//     its block-sparse copy of W each solve and then allocates as the sparse path does (sparse_pgs.h);
//     with equality rows, the condensed problem (W_ee's LDLT, W_ee⁺ W_ec and the Schur complement),
//     once per solve.
#pragma once

#include "contact/coulomb_local.h"
#include "contact/friction_contact_problem.h"

#include <Eigen/Dense>
#include <vector>

namespace csim {

struct PgsParameters {
  int max_iterations = 2000;  // sweeps
  double tolerance = 1e-12;   // relative residual (see above), dimensionless
  double omega = 1.0;         // relaxation, (0, 2)
  // With omega = 1, the sparse path over-relaxes (1.5) until its sweeps stall, then goes on at 1
  // (sparse_pgs.h); false, or any other omega, relaxes by omega throughout on both paths.
  bool relax_sparse = true;
  bool polish = true;         // the direct polish (above)
  // Both paths: the polish's work is at most polish_budget times the sweeps' work so far plus
  // polish_allowance (all in flops, PgsStatistics::polish_work and sweep_work): the allowance, about
  // a millisecond, lets a small problem's few sweeps be finished.
  double polish_budget = 10.0;
  double polish_allowance = 1e6;
  // A W stored dense but mostly zero blocks (at least 150 rows, at most 25 % of its D × D blocks
  // nonzero, no equality rows) is solved on a block-sparse copy by the sparse path (sparse_pgs.h),
  // whose sweeps and polish cost O(nonzero blocks); docs/contact-problems.md ("The polish on W stored
  // dense and by blocks") gives the times of both paths and the bench_polish command that measures
  // them. false keeps the dense path.
  bool route_sparse = true;
};

struct PolishBudget;  // polish_budget.h

struct PgsStatistics {
  int iterations = 0;         // sweeps done
  double residual = 0.0;      // final full residual, relative
  bool converged = false;
  int rejected_local_solutions = 0;  // non-finite local results filtered out
  bool polished = false;      // the polish improved the iterate
  int polishes = 0;           // polishes run (each: the active-set iteration and Newton, see above)
  double sweep_work = 0.0;    // flops of the sweeps' products by W (2 per stored entry and sweep)
  double polish_work = 0.0;   // flops of the polish (factorizations, solves, products)
  int polish_factorizations = 0;  // LU factorizations of the polish (sparse path: sparse ones)
  bool polish_cut = false;    // a polish stopped at its budget
  bool routed_to_sparse = false;  // a dense-stored W was solved on its block-sparse copy (route_sparse)
  // The dense path's reading of W's rows (above): sweeps on W's own columns as its rows (W symmetric
  // to round-off, not to the bit), and whether Wᵀ was copied (W further from symmetric, or the
  // near-symmetric sweeps' answer missed the tolerance on W's own rows and the solve went on from it
  // on the copy).
  int near_symmetric_sweeps = 0;
  bool transposed = false;

  // One polish on either path: start_polish counts it and gives the flops it may spend (parameters'
  // polish_budget × sweep_work + polish_allowance − polish_work); finish_polish records what it spent.
  PolishBudget start_polish(const PgsParameters& parameters);
  void finish_polish(const PolishBudget& budget, bool improved);
  // The work of another solve of the same problem or of a part of it (a relaxed attempt, an island, a
  // fallback) added to this one's: counts and flops summed, flags or-ed. Not the sweeps (iterations),
  // residual or convergence, which the caller combines by its own rule.
  void add_work(const PgsStatistics& other);
};

// The work arrays of a solve with equality rows (their condensation, equality_condensation.cpp): a solver keeps
// them, so that a stepper's solves allocate nothing once they have the problem's size.
struct PgsCondensation {
  FrictionContactProblem contacts;  // the contact rows only, the equalities condensed out
  bool symmetric = true;             // W equals its transpose to the bit: W_ee by its LDLT, else by W_ee_general
  Eigen::LDLT<Eigen::MatrixXd> W_ee;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> W_ee_general;
  Eigen::MatrixXd W_transpose;      // Wᵀ when W is not symmetric (its rows, read as columns), else empty
  Eigen::MatrixXd X;                // W_ee⁺ W_ec
  Eigen::VectorXd x_b;              // W_ee⁺ b_e
  Eigen::VectorXd full_scale, r_c, r_e, u_e, product;
  Eigen::VectorXd full_r;           // the full impulses at a convergence test of the condensed iteration
  // The full W (and its split) that W_ee, X and the condensed W were formed from: a problem whose W
  // is the same to the bit (a lumped World's constant rows, step after step) reuses them.
  Eigen::MatrixXd W;
  int dimension = 0, contact_count = -1, equalities = -1;
  // x ← W_ee⁺ x: the LDLT's solve; for a single equality row written out (a point held on a line),
  // the same to the bit without the solve's set-up. Of an unsymmetric W, W_ee_general's solve.
  void solve_equalities(Eigen::VectorXd& x) const;
};

class PgsSolver {
 public:
  explicit PgsSolver(PgsParameters parameters = {}) : parameters_(parameters) {}

  // r: on entry the warm start (resized and zeroed if its size differs from problem.size()), on exit
  // the solution. status (optional) receives one ContactStatus per contact.
  PgsStatistics solve(const FrictionContactProblem& problem, Eigen::VectorXd& r,
                      std::vector<ContactStatus>* status = nullptr) const;

  // The full residual of the law at r, as defined above (used by tests and by callers that only check).
  static double residual(const FrictionContactProblem& problem, const Eigen::VectorXd& r);

  const PgsParameters& parameters() const { return parameters_; }

 private:
  PgsStatistics solve_routed(const FrictionContactProblem& problem, Eigen::VectorXd& r,
                             std::vector<ContactStatus>* status) const;
  PgsParameters parameters_;
  // Work arrays, not state: a copy of the solver starts with its own, empty. One thread per solver
  // (a stepper's own), hence mutable in a const solve.
  struct Scratch {
    PgsCondensation condensation;
    Eigen::MatrixXd transpose;  // Wᵀ of the contact rows' problem, when W is not symmetric
    Eigen::VectorXd product;    // W r of a near-symmetric W's residual (dense_pgs.h)
    SparseDelassus completed;   // a sparse W completed to whole blocks, when the problem's is not
    FrictionContactProblem routed;  // a dense-stored W's block-sparse copy (route_sparse)
    Scratch() = default;
    Scratch(const Scratch&) {}
    Scratch& operator=(const Scratch&) { return *this; }
  };
  mutable Scratch scratch_;
};

}  // namespace csim
