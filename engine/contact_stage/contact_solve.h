// The parts of a step's frictional contact solve that every stepper shares: the warm start from the
// last step's impulses (matched by contact key), the projected Gauss–Seidel solve with its counters,
// and the failure message (a solve left above contact_solver.failure_residual stops the run).
#pragma once

#include "contact/pgs_solver.h"
#include "engine/state.h"

#include <string>
#include <vector>

namespace csim {

// r (size problem.size()) gets the previous impulses of the contacts with the same key, zeros elsewhere;
// status, when given, their previous statuses (open for a new contact).
void warm_start(const std::vector<ActiveContact>& previous, const std::vector<ActiveContact>& active,
                int dimension, int size, Vector& r, std::vector<ContactStatus>* status = nullptr);

// Solves, accounts in state.counters, and copies the impulses and statuses back into `active`.
// A problem of at least 150 rows whose W splits into islands (contact/islands.h: contacts that share no
// moving body) is solved island by island, each to tolerance / √(islands), an island of fewer than 150 rows stored dense; the
// whole problem's residual then decides convergence, and a split solve that misses it is followed by a
// solve of the whole problem from its iterate (the better of the two kept). The counters see one solve,
// its sweeps the most any island took.
// Returns "" or, for a solve left above the failure threshold, the message that stops the run; the
// caller throws it (Moreau–Jean at once; the quasi-static stepper only if it is the solve of the
// Newton iterate it accepts). t_next: the time the step reaches (s). status_scratch, when given,
// holds the solver's statuses (a stepper's own, so that a step allocates nothing).
// A problem stored sparse whose solve does not converge is solved again stored dense, from the same warm
// start, when it has at most kDenseFallbackRows rows (W then takes 134 MB at most): the sparse solver's
// polish (a bounded Newton without the dense one's active-set stage, pgs_solver.h) can stall on a
// hyperstatic stack that the dense polish finishes (and the dense solve started from the sparse one's
// stalled iterate stalls as well). If neither converges, the iterate of smaller residual is kept and
// reported unconverged. SolverCounters::dense_fallbacks counts them.
// A solve from a nonzero warm start that still does not converge is then taken again from r = 0 (the
// better of the two kept; SolverCounters::cold_restarts): Gauss–Seidel on a hyperstatic frictional set
// can stall from the last step's impulses where it converges from zero (scenes/sphere-drop's generator,
// 8 spheres, seed 1: 5.5e-5 after 20 000 sweeps warm, 6e-12 in 200 cold; over six counts and seeds the
// solves left above 1e-6 went from 13 and two stopped runs to 2 and one).
// A solve still unconverged is last taken again from r = 0 by the sweeps alone (no polish, no relaxed
// attempt, ω = 1; the better kept; SolverCounters::sweeps_only_retries): a polish whose result lowers the
// residual without converging replaces Gauss–Seidel's iterate, and on a settling pile the sweeps from
// that point can stall where their own sequence converges (27 spheres, seed 1, at 0.587 s: 3.2e-5 after
// 20 000 sweeps with the polish, warm or cold; 7.9e-7 in 7 937 sweeps alone from zero).
constexpr int kDenseFallbackRows = 4096;
[[nodiscard]] std::string solve_contacts(const PgsSolver& pgs, const FrictionContactProblem& problem,
                                         double failure_residual, double t_next, Vector& r,
                                         std::vector<ActiveContact>& active, SolverCounters& counters,
                                         std::vector<ContactStatus>* status_scratch = nullptr);

}  // namespace csim
