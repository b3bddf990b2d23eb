// The iteration that both of PgsSolver's paths run (pgs_solver.h states it; dense W: pgs_solver.cpp,
// sparse W: sparse_pgs.cpp): sweeps, the cheap test then the full residual, and when to polish.
// Internal to contact/.
//
// A path gives, on its own storage of W:
//   SweepResult sweep(Eigen::VectorXd& r, int& rejected)      one Gauss–Seidel sweep (pgs_local.h);
//   double sweep_flops() const                                its products by W (2 per stored entry);
//   double residual(const Eigen::VectorXd& r, int settled_from) const   the full relative residual;
//   bool polish(Eigen::VectorXd& r, double& residual, PolishBudget& budget)   true if r was replaced;
//   void observe(const SweepResult& swept, double scale)      sees each sweep's increment (scale: m/s);
//   bool stalled() const                                      false skips a scheduled polish;
//   bool retries_skipped_polish() const                       true: a skipped polish is tried again
//                                                             kFirstPolish sweeps later (until the next
//                                                             scheduled one);
//   bool at_floor() const                                     true ends the solve after a residual test
//                                                             above tolerance (its residual cannot fall);
//   bool gives_up() const                                     true ends the solve after the sweep just
//                                                             observed (a relaxed attempt that stalls,
//                                                             sparse_pgs.h).
//   bool ends_with_polish() const                             false skips the final polish of an
//                                                             unconverged solve (a path that another
//                                                             one continues, pgs_solver.cpp).
// The sparse path skips while the sweeps converge at a steady rate (sparse_pgs.h) and waits for the next
// schedule; the dense path skips only while that rate reaches the tolerance within ten sweeps
// (pgs_solver.cpp), and tries again kFirstPolish sweeps later; the condensed path polishes on every
// schedule.
#pragma once

#include "contact/pgs_local.h"
#include "contact/pgs_solver.h"
#include "contact/polish_budget.h"

#include <cmath>
#include <limits>
#include <vector>

namespace csim::pgs_local {

// Sweeps between two attempts at the polish.
constexpr int kPolishInterval = 200;
// ... and once early, after 20 sweeps: when a few sweeps have sorted out the statuses, the direct
// solve finishes a problem that Gauss–Seidel would take hundreds of sweeps over (an ill-conditioned
// Delassus). A dense sweep costs 2 m² flops for m rows and an LU of the polish 2 m³/3, so the polish's
// budget (PgsParameters) lets it factor a few hundred rows at sweep 20 and more at later attempts.
constexpr int kFirstPolish = 20;

// The contraction per sweep of the relative increments ‖Δr‖ / scale, from the last kWindow + 1 sweeps:
// (increment_k / increment_{k−kWindow})^(1/kWindow); infinite until kWindow + 1 sweeps are known or
// when an increment is zero (a sweep that moved nothing is followed by the full residual's test).
// A sweep stores its sums as they are (‖Δr‖², (m/s)², and the scale, m/s): the square roots and
// quotients are taken only when the contraction is asked for, at a scheduled polish.
class ContractionWindow {
 public:
  static constexpr int kWindow = 10;
  void add(double increment_squared, double scale) {
    increments_squared_[slot_] = increment_squared;
    scales_[slot_] = scale;
    slot_ = slot_ == kWindow ? 0 : slot_ + 1;
    if (count_ <= kWindow) ++count_;
  }
  // The newest relative increment, and the one kWindow sweeps before it (0 until known).
  double newest() const { return count_ > 0 ? relative(slot_ == 0 ? kWindow : slot_ - 1) : 0.0; }
  double oldest() const { return count_ > kWindow ? relative(slot_) : 0.0; }
  double contraction() const {
    const double newest_increment = newest(), oldest_increment = oldest();
    if (!(oldest_increment > 0.0) || !(newest_increment > 0.0)) return std::numeric_limits<double>::infinity();
    return std::pow(newest_increment / oldest_increment, 1.0 / kWindow);
  }

 private:
  double relative(int slot) const { return std::sqrt(increments_squared_[slot]) / scales_[slot]; }
  // Read only where written (count_ says how many are): left uninitialized, so that a solve of a few
  // sweeps does not pay for clearing them. slot_ is the next to write, which once the window is full
  // holds the oldest.
  double increments_squared_[kWindow + 1];
  double scales_[kWindow + 1];
  int slot_ = 0, count_ = 0;
};

// The solve of a problem without contacts (nothing to sweep): converged, no status.
inline PgsStatistics without_contacts(std::vector<ContactStatus>* status) {
  if (status != nullptr) status->clear();
  PgsStatistics statistics;
  statistics.converged = true;
  return statistics;
}

// `start`: the statistics of an earlier iteration on the same problem that this one continues from r
// (its sweeps count towards max_iterations and the polish's budget, and set the polish's schedule);
// `last_polish`: on entry the sweep count at that iteration's last polish (−1: none), on exit this
// one's (null: not asked).
template <int D, class Path>
PgsStatistics iterate(const FrictionContactProblem& problem, const PgsParameters& parameters, Path& path,
                      Eigen::VectorXd& r, std::vector<ContactStatus>* status, const PgsStatistics& start = {},
                      int* last_polish = nullptr) {
  PgsStatistics statistics = start;
  const double sweep_flops = path.sweep_flops();
  // The sweep count at the last polish: the final polish is skipped when no sweep has run since the
  // last one. With max_iterations 20 or a multiple of 200 an unconverged solve used to polish twice in
  // a row, the second from the first one's result: twice the cost (23.9 s became 47.9 s on a
  // 296-contact problem) for at most a small gain (rolling-ring-3d-cornering, whose 7 unconverged
  // solves end at a relative residual of 3e-3 either way).
  int polished_after = last_polish != nullptr ? *last_polish : -1;
  const auto polish_now = [&] {
    polished_after = statistics.iterations;
    PolishBudget budget = statistics.start_polish(parameters);
    statistics.finish_polish(budget, path.polish(r, statistics.residual, budget));
  };

  const double norm_b = problem.b.norm();
  bool residual_is_current = false;
  int retry_at = -1;  // the sweep at which a skipped polish is tried again
  for (int iteration = statistics.iterations + 1; iteration <= parameters.max_iterations; ++iteration) {
    const SweepResult swept = path.sweep(r, statistics.rejected_local_solutions);
    statistics.iterations = iteration;
    statistics.sweep_work += sweep_flops;
    residual_is_current = false;
    const double scale = velocity_scale(norm_b, std::sqrt(swept.Wr_squared));
    path.observe(swept, scale);
    if (path.gives_up()) break;
    // A stalled iteration: try the polish every kPolishInterval sweeps.
    const bool polish_due = iteration % kPolishInterval == 0 || iteration == kFirstPolish || iteration == retry_at;
    if (parameters.polish && polish_due && !path.stalled()) {
      if (path.retries_skipped_polish()) retry_at = iteration + kFirstPolish;
    } else if (parameters.polish && polish_due) {
      statistics.residual = path.residual(r, swept.settled_from);
      residual_is_current = true;
      polish_now();
      if (statistics.residual <= parameters.tolerance) {
        statistics.converged = true;
        break;
      }
      if (path.at_floor()) break;
      continue;
    }
    // Cheap test: a sweep that barely moved r, or one after which every contact is settled (the full
    // residual then costs no local solve, and the next sweep would return r to the bit: a single
    // contact is solved by its first sweep). Only then is the full residual (about one more sweep of
    // work) worth computing; it decides.
    if (swept.settled_from == 0 || std::sqrt(swept.increment_squared) <= parameters.tolerance * scale) {
      statistics.residual = path.residual(r, swept.settled_from);
      residual_is_current = true;
      if (statistics.residual <= parameters.tolerance) {
        statistics.converged = true;
        break;
      }
      if (path.at_floor()) break;
    }
  }
  if (!residual_is_current) {
    statistics.residual = path.residual(r, problem.contacts);
    statistics.converged = statistics.residual <= parameters.tolerance;
  }
  if (parameters.polish && path.ends_with_polish() && !statistics.converged &&
      polished_after != statistics.iterations) {
    polish_now();
    statistics.converged = statistics.residual <= parameters.tolerance;
  }

  if (last_polish != nullptr) *last_polish = polished_after;
  if (status != nullptr) {
    status->resize(static_cast<std::size_t>(problem.contacts));
    for (int c = 0; c < problem.contacts; ++c)
      (*status)[c] = status_of<D>(r.template segment<D>(static_cast<Eigen::Index>(D) * c), problem.mu[c]);
  }
  return statistics;
}

}  // namespace csim::pgs_local
