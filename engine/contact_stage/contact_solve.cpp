#include "engine/contact_stage/contact_solve.h"

#include "engine/steppers/stepper.h"

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

std::string solve_contacts(const PgsSolver& pgs, const FrictionContactProblem& problem, double failure_residual,
                           double t_next, Vector& r, std::vector<ActiveContact>& active, SolverCounters& c,
                           std::vector<ContactStatus>* status_scratch) {
  if (problem.size() == 0) return "";
  std::vector<ContactStatus> own_status;
  std::vector<ContactStatus>& status = status_scratch ? *status_scratch : own_status;
  status.clear();
  const bool may_fall_back = problem.storage == DelassusStorage::sparse && problem.size() <= kDenseFallbackRows;
  Vector start;
  if (may_fall_back) start = r;
  PgsStatistics stats = pgs.solve(problem, r, &status);
  if (!stats.converged && may_fall_back) {
    FrictionContactProblem dense = problem;
    dense.storage = DelassusStorage::dense;
    dense.W = Matrix(problem.W_sparse);
    dense.W_sparse.resize(0, 0);
    const PgsStatistics sparse_stats = stats;
    Vector sparse_r = r;
    std::vector<ContactStatus> sparse_status = status;
    r = start;  // the dense solve from the warm start: from the sparse iterate it may stall too
    PgsParameters dense_path = pgs.parameters();  // the dense path itself, not the route back to sparse
    dense_path.route_sparse = false;
    stats = PgsSolver(dense_path).solve(dense, r, &status);
    if (!stats.converged && sparse_stats.residual < stats.residual) {  // the better of two unconverged
      stats.residual = sparse_stats.residual;
      r = sparse_r;
      status = sparse_status;
    }
    stats.iterations += sparse_stats.iterations;
    ++c.dense_fallbacks;
  }
  return account(stats, problem.dimension, failure_residual, t_next, r, status, active, c);
}

}  // namespace csim
