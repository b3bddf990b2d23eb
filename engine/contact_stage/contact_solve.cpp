#include "engine/contact_stage/contact_solve.h"

#include "contact/islands.h"
#include "engine/steppers/stepper.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace csim {

void warm_start(const std::vector<ActiveContact>& previous, const std::vector<ActiveContact>& active,
                int dimension, int size, Vector& r, std::vector<ContactStatus>* status) {
  r.setZero(size);
  if (status) status->assign(active.size(), ContactStatus::open);
  std::size_t j = 0;  // both lists are sorted by key
  for (std::size_t i = 0; i < active.size(); ++i) {
    const ContactKey& key = active[i].point.key;
    while (j < previous.size() && previous[j].point.key < key) ++j;
    if (j < previous.size() && previous[j].point.key == key) {
      for (int k = 0; k < dimension; ++k) r(dimension * i + k) = previous[j].impulse(k);
      if (status) (*status)[i] = previous[j].status;
    }
  }
}

namespace {

std::string account(const PgsStatistics& stats, int dimension, double failure_residual, double t_next,
                    const Vector& r, const std::vector<ContactStatus>& status, std::vector<ActiveContact>& active,
                    SolverCounters& c) {
  ++c.solves;
  c.total_iterations += stats.iterations;
  c.max_iterations = std::max(c.max_iterations, stats.iterations);
  c.max_residual = std::max(c.max_residual, stats.residual);
  c.rejected_local_solutions += stats.rejected_local_solutions;
  for (std::size_t i = 0; i < active.size(); ++i) {
    active[i].impulse.head(dimension) = r.segment(dimension * i, dimension);
    active[i].status = status.empty() ? ContactStatus::open : status[i];
  }
  if (stats.converged) return "";
  if (c.not_converged++ == 0) c.first_not_converged_time = t_next;
  if (stats.residual <= failure_residual) return "";
  std::ostringstream failure;
  failure << "contact solver failed at t = " << t_next << " s: residual " << stats.residual << " after "
          << stats.iterations << " iterations (failure threshold contact_solver.failure_residual = "
          << failure_residual << ")";
  return failure.str();
}

}  // namespace

namespace {

// An unconverged solve (stats, r, status) against a second solve of `problem` by `solver` from `start`:
// the second is kept if it converged or its residual is no larger; the sweeps and work of both counted.
void solve_again(const PgsSolver& solver, const FrictionContactProblem& problem, Vector start, Vector& r,
                 std::vector<ContactStatus>& status, PgsStatistics& stats) {
  std::vector<ContactStatus> again_status;
  PgsStatistics again = solver.solve(problem, start, &again_status);
  const int sweeps = stats.iterations + again.iterations;
  if (again.converged || again.residual <= stats.residual) {
    again.add_work(stats);
    stats = again;
    r.swap(start);
    status.swap(again_status);
  } else {
    stats.add_work(again);
  }
  stats.iterations = sweeps;
}

// One problem: PGS, then for a sparse one that did not converge the dense fallback, then for a solve
// still unconverged from a nonzero warm start the cold restart (header).
PgsStatistics solve_one(const PgsSolver& pgs, const FrictionContactProblem& problem, Vector& r,
                        std::vector<ContactStatus>& status, SolverCounters& c) {
  const bool may_fall_back = problem.storage == DelassusStorage::sparse && problem.size() <= kDenseFallbackRows;
  const bool warm = !r.isZero(0.0);
  Vector start;  // the warm start, kept only for the dense fallback (no copy a solve otherwise)
  if (may_fall_back) start = r;
  PgsStatistics stats = pgs.solve(problem, r, &status);
  if (!stats.converged && may_fall_back) {
    // From the warm start: from the sparse iterate the dense solve may stall too.
    FrictionContactProblem dense = problem;
    dense.storage = DelassusStorage::dense;
    dense.W = Matrix(problem.W_sparse);
    dense.W_sparse.resize(0, 0);
    dense.body_blocks.clear();  // W's factors go with the sparse storage (friction_contact_problem.h)
    PgsParameters dense_path = pgs.parameters();  // the dense path itself, not the route back to sparse
    dense_path.route_sparse = false;
    solve_again(PgsSolver(dense_path), dense, std::move(start), r, status, stats);
    ++c.dense_fallbacks;
  }
  if (!stats.converged && warm) {
    solve_again(pgs, problem, Vector::Zero(r.size()), r, status, stats);
    ++c.cold_restarts;
  }
  if (!stats.converged && pgs.parameters().polish) {
    PgsParameters sweeps_only = pgs.parameters();  // Gauss–Seidel's own iterate, from zero (header)
    sweeps_only.polish = false;
    sweeps_only.relax_sparse = false;
    sweeps_only.omega = 1.0;
    solve_again(PgsSolver(sweeps_only), problem, Vector::Zero(r.size()), r, status, stats);
    ++c.sweeps_only_retries;
  }
  return stats;
}

// An island of fewer rows is stored dense: PgsSolver routes no dense W under 150 rows to the sparse path
// (pgs_solver.h, route_sparse), and small problems are solved fastest dense (docs/contact-problems.md).
// Not so an island of a problem with body blocks (friction_contact_problem.h): its sweeps through the
// bodies' velocities beat the dense rows whatever its size (`csim run` of `bench_drop spheres 343 300 1
// --scene`: 8.24e9 instructions with such islands dense, 7.22e9 with them sparse, same sweeps to 2 %).
constexpr int kDenseIslandRows = 150;

// Island by island (contact/islands.h), each to tolerance / √(islands): W being block diagonal over them,
// the whole residual's square is the sum of theirs, each relative to a scale max(‖b_i‖, ‖W_i r_i‖) no
// larger than the whole one's, so the whole residual is then within the tolerance. It is computed and
// decides convergence all the same.
PgsStatistics solve_islands(const PgsSolver& pgs, const FrictionContactProblem& problem,
                            const std::vector<std::vector<int>>& islands, Vector& r, std::vector<ContactStatus>& status,
                            SolverCounters& c) {
  PgsParameters parameters = pgs.parameters();
  parameters.tolerance /= std::sqrt(static_cast<double>(islands.size()));
  const PgsSolver island_solver(parameters);
  const int d = problem.dimension;
  status.assign(problem.contacts, ContactStatus::open);
  PgsStatistics total;
  bool every_island_converged = true;
  std::vector<ContactStatus> island_status;
  for (const std::vector<int>& contacts : islands) {
    const bool small = d * static_cast<int>(contacts.size()) < kDenseIslandRows && problem.body_blocks.empty();
    const DelassusStorage storage = small ? DelassusStorage::dense : problem.storage;
    const FrictionContactProblem island = island_problem(problem, contacts, storage);
    Vector island_r = gather_island(contacts, d, r);
    const PgsStatistics s = solve_one(island_solver, island, island_r, island_status, c);
    scatter_island(contacts, d, island_r, &island_status, r, &status);
    every_island_converged = every_island_converged && s.converged;
    total.iterations = std::max(total.iterations, s.iterations);
    total.add_work(s);
  }
  total.residual = PgsSolver::residual(problem, r);
  total.converged = every_island_converged && total.residual <= pgs.parameters().tolerance;
  return total;
}

}  // namespace

std::string solve_contacts(const PgsSolver& pgs, const FrictionContactProblem& problem, double failure_residual,
                           double t_next, Vector& r, std::vector<ActiveContact>& active, SolverCounters& c,
                           std::vector<ContactStatus>* status_scratch) {
  if (problem.size() == 0) return "";
  std::vector<ContactStatus> own_status;
  std::vector<ContactStatus>& status = status_scratch ? *status_scratch : own_status;
  status.clear();
  // A problem of fewer rows than an island stored dense is solved whole: splitting it would save
  // little, and finding its islands costs a lumped step a tenth of its instructions (sdnv104-rigid).
  const std::vector<std::vector<int>> islands =
      problem.size() < kDenseIslandRows ? std::vector<std::vector<int>>{} : find_islands(problem);
  if (islands.size() <= 1) {
    const PgsStatistics stats = solve_one(pgs, problem, r, status, c);
    return account(stats, problem.dimension, failure_residual, t_next, r, status, active, c);
  }
  if (r.size() != problem.size()) r.setZero(problem.size());  // a stale warm start, as PgsSolver reads one
  PgsStatistics stats = solve_islands(pgs, problem, islands, r, status, c);
  if (!stats.converged) {
    // The whole problem from the islands' iterate; the better of the two is kept.
    const PgsStatistics island_stats = stats;
    const Vector island_r = r;
    const std::vector<ContactStatus> island_status = status;
    stats = solve_one(pgs, problem, r, status, c);
    if (!stats.converged && island_stats.residual < stats.residual) {
      stats.residual = island_stats.residual;
      r = island_r;
      status = island_status;
    }
    stats.iterations += island_stats.iterations;
  }
  return account(stats, problem.dimension, failure_residual, t_next, r, status, active, c);
}

}  // namespace csim
