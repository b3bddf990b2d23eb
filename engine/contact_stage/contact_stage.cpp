#include "engine/contact_stage/contact_stage.h"

#include "engine/contact_stage/contact_solve.h"
#include "engine/steppers/stepper.h"

#include <algorithm>

namespace csim {

ContactStage::ContactStage(const World& world, const PgsParameters& solver, std::unique_ptr<IterationOperator> iteration)
    : world_(world), touching_(kTouching * world.length_scale()), detector_(world), dimension_(detector_.dimension()),
      pgs_(solver), iteration_(std::move(iteration)) {
  rows_.dimension = dimension_;
}

void ContactStage::detect(const Vector& q, double margin) {
  active_.clear();
  active_candidates_.clear();
  detector_.detect(q, margin + touching_, candidates_, candidate_rows_);
}

bool ContactStage::is_active(int k) const {
  return std::binary_search(active_candidates_.begin(), active_candidates_.end(), k);
}

void ContactStage::activate(int k) {
  active_.push_back(candidates_[k]);
  active_candidates_.push_back(k);
}

void ContactStage::activate_more(const std::vector<int>& more) {
  std::vector<int> merged(active_candidates_.size() + more.size());
  std::merge(active_candidates_.begin(), active_candidates_.end(), more.begin(), more.end(), merged.begin());
  active_candidates_ = std::move(merged);
  active_.clear();
  for (int k : active_candidates_) active_.push_back(candidates_[k]);
}

void ContactStage::warm_start_from(const std::vector<ActiveContact>& previous, std::vector<ContactStatus>* statuses) {
  warm_start(previous, active_, dimension_, problem_.size(), r_, statuses);
}

std::string ContactStage::solve_from_impulses(double failure_residual, double t_next, SolverCounters& counters) {
  return solve_contacts(pgs_, problem_, failure_residual, t_next, r_, active_, counters, &statuses_);
}

void ContactStage::gather_rows(const Matrix* equalities, const std::vector<SparseRow>* ties, double t) {
  const int d = dimension_;
  const int nc = static_cast<int>(active_.size());
  rows_.contact.resize(d * nc);
  rows_.contact_candidate = active_candidates_;
  rows_.contact_key.resize(nc);
  rows_.candidates = static_cast<int>(candidates_.size());
  rows_.equalities = equalities;
  rows_.ties = ties;
  problem_.dimension = d;
  problem_.contacts = nc;
  problem_.equalities = rows_.equality_rows() + rows_.tie_rows();
  problem_.mu.resize(nc);
  for (int i = 0; i < nc; ++i) {
    for (int k = 0; k < d; ++k) rows_.contact[d * i + k] = &candidate_rows_[d * active_candidates_[i] + k];
    rows_.contact_key[i] = active_[i].point.key;
    problem_.mu[i] = world_.contact_laws[active_[i].law].mu_at(t);
  }
  iteration_->gather(rows_);
}

void ContactStage::solve(const std::vector<ActiveContact>& previous, bool warm_from_previous, double failure_residual,
                         double t_next, SolverCounters& counters) {
  if (warm_from_previous || r_.size() != problem_.size()) warm_start(previous, active_, dimension_, problem_.size(), r_);
  const long stored = problem_.storage == DelassusStorage::sparse ? static_cast<long>(problem_.W_sparse.nonZeros())
                                                                   : static_cast<long>(problem_.W.size());
  counters.max_delassus_entries = std::max(counters.max_delassus_entries, stored);
  if (problem_.storage == DelassusStorage::sparse) ++counters.sparse_solves;
  if (const std::string failure =
          solve_contacts(pgs_, problem_, failure_residual, t_next, r_, active_, counters, &statuses_);
      !failure.empty())
    throw RunError(t_next, failure);
}

void ContactStage::form_delassus() {
  if (choice_ != DelassusChoice::dense &&
      iteration_->sparse_delassus(rows_, problem_.W_sparse, choice_ == DelassusChoice::sparse)) {
    problem_.storage = DelassusStorage::sparse;
    problem_.W.resize(0, 0);
    if (!iteration_->body_blocks(problem_.body_blocks)) problem_.body_blocks.clear();
    return;
  }
  problem_.body_blocks.clear();
  problem_.storage = DelassusStorage::dense;
  if (problem_.W_sparse.outerSize() != 0) problem_.W_sparse.resize(0, 0);  // resize allocates: not every step
  iteration_->delassus(rows_, problem_.W);
}

}  // namespace csim
