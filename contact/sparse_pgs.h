// Projected Gauss–Seidel on a sparse Delassus operator (storage sparse, friction_contact_problem.h):
// the sparse path of PgsSolver (pgs_solver.h states the method, the convergence test and the statuses;
// this path follows them, with these differences).
//
//   - A sweep reads, for each contact, its D rows of W_sparse (compressed rows: contiguous), skipping
//     its own diagonal block, so it costs O(stored entries); the diagonal blocks are copied out once
//     per solve, and in 3D their stick inverses formed once (coulomb_local.h). No m × m matrix is formed
//     anywhere on this path. Rows are what the law reads, so an unsymmetric W needs no transpose.
//   - With W's body-block factors (problem.body_blocks, friction_contact_problem.h: an A block diagonal
//     by body, rigid bodies and point masses) the sweeps apply W matrix-free, as sequential-impulse
//     solvers do: the bodies' scaled velocities w = Σ_c K_cᵀ r_c are kept, a contact's velocity is
//     b_c + K_c w (its two bodies' 2 · D · 6 products), and its change of impulse is added to its
//     bodies' w after its local solve. The residual is the same quantity, b + W r from K (w formed
//     again from r for each); the polish, the sweep work counted (2 per stored entry of W_sparse, so
//     that the polish's budget is unchanged) and every other reader of W use W_sparse. Per contact
//     update the products cost about what reading 8 neighbour blocks costs; the gain grows with the
//     contacts a body has (bench/lumped_vs_bullet.md, the dropped spheres).
//   - W_sparse is used as it is when its pattern is made of whole D × D blocks in sorted compressed
//     rows and holds every diagonal block; otherwise a copy so completed (explicit zeros) is made once
//     per solve.
//   - The polish: the Alart–Curnier Newton method on W's sparse pattern (sparse_alart_curnier.h: a
//     sparse LU, a proximal step on a rank-deficient W) from the Gauss–Seidel iterate, with ρ scales 1
//     and 1e3; if it does not reach the tolerance, the active-set iteration (sparse_active_set.h: the
//     statuses' system solved as a proximal correction of the iterate by a sparse LU, sound on the
//     singular W of a hyperstatic set) from the iterate's statuses, then from "every closed contact in
//     stick", each stopped as soon as a pass's candidate is no closer to the law than the last pass's,
//     and Newton from its result. Each result is kept only when its full residual is smaller. Newton
//     comes first (the dense path's order is the reverse): on granular flows the statuses wander and
//     the active set would spend the budget Newton needs. Its work (flops) is bounded:
//     polish work ≤ PgsParameters::polish_budget × the sweeps' work so far + polish_allowance
//     (PgsStatistics::sweep_work, polish_work); a polish that would exceed it is cut before the factorization that would.
//   - The schedule is the dense path's (after 20 sweeps, every 200, at the end), except that a scheduled
//     polish is skipped while the sweeps converge at a steady rate: their relative increments
//     contracting by less than 0.99 a sweep over the last 10 (a decade in at most 230 sweeps). The
//     sweeps then finish for less than the polish would spend (Siconos' FrictionContactProblem00727:
//     696 sweeps alone in 29 ms; 400 sweeps and three polishes in 260 ms). A solve that ends
//     unconverged is polished at the end as before.
//   - A relaxed attempt first: with PgsParameters::relax_sparse and omega = 1 (the defaults) a solve
//     first sweeps relaxed by 1.5 (pulled back into the cone, pgs_solver.h), without the polish, for
//     at most 200 sweeps, given up at the first window of 11 sweeps that stalls (the contraction test
//     above); unconverged, it is solved again from the same warm start as without the attempt, so
//     that it ends where it did without it, for the attempt's sweeps more. Switching to omega = 1 in
//     the middle of the solve instead left the packed box of spheres (sparse_pgs_test.cpp) at 1e-6
//     after 17 000 sweeps where it converges in 1 400. Sweeps a solve, dropped spheres (bench_drop,
//     300 steps of 1 ms, tolerance 1e-6): 343 spheres 95 → 45, 1000 spheres 119 → 63; Siconos'
//     problems (docs/contact-problems.md) gain on three and pay 11 to 200 sweeps on the others.
//     The attempt's sweeps count in the statistics.
//   - Allocation: each solve copies the diagonal blocks and their offsets (O(contacts)); a polish
//     allocates J's values (W's size) and UMFPACK's factors. The dense path's no-allocation promise
//     (pgs_solver.h) is not this path's.
//   - Speed (bench/bench_pgs): on a W where every block is stored the dense path's sweep is 1.1 to 4
//     times faster; on a block-tridiagonal chain this path's is as fast from 4 contacts and 3 to 30
//     times faster from 100 to 1000. A dense-stored W of at least 150 rows and at most 25 % nonzero
//     blocks is routed here by PgsSolver (PgsParameters::route_sparse).
//   - Equality rows are not condensed sparsely: a sparse problem with equalities throws
//     std::invalid_argument (store W dense for such a problem).
#pragma once

#include "contact/pgs_solver.h"

namespace csim {

PgsStatistics solve_sparse(const FrictionContactProblem& problem, const PgsParameters& parameters, Eigen::VectorXd& r,
                           std::vector<ContactStatus>* status, SparseDelassus& completed);

// The full residual of pgs_solver.h on a sparse problem.
double sparse_residual(const FrictionContactProblem& problem, const Eigen::VectorXd& r);

// W as a block-sparse matrix of whole blocks (its nonzero D × D blocks and every diagonal block), for
// the sparse path of a dense problem.
SparseDelassus block_sparse(const Eigen::MatrixXd& W, int dimension);

}  // namespace csim
