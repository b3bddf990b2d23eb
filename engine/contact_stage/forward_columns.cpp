#include "engine/contact_stage/forward_columns.h"

#include "engine/structural_operators.h"

namespace csim {

namespace {

// A row's identity in the cache: a contact's k-th row, an equality's row e, a tie's row i.
constexpr int kContactRow = 0, kEqualityRow = 1, kTieRow = 2;

}  // namespace

int ForwardColumnsOperator::equality_slot(const Matrix& equalities, int e) {
  equality_index_.clear();
  equality_value_.clear();
  for (int j = 0; j < equalities.cols(); ++j)
    if (equalities(e, j) != 0.0) {
      equality_index_.push_back(j);
      equality_value_.push_back(equalities(e, j));
    }
  return cache_.slot({kEqualityRow, {}, e}, equality_index_.data(), equality_value_.data(),
                     static_cast<int>(equality_index_.size()));
}

void ForwardColumnsOperator::take_slots(const ProblemRows& rows) {
  const int m = rows.size();
  const int d = rows.dimension;
  const int nc = rows.contact_rows(), ne = rows.equality_rows();
  slots_.resize(m);
  if (halves_) {  // the candidates' slots (gather_candidates), then the equalities'
    for (int a = 0; a < m; ++a) slots_[a] = candidate_slots_[rows.candidate_row(a)];
    return;
  }
  cache_.begin(operators_.sparse_factor());
  for (int a = 0; a < nc; ++a) {
    const SparseRow& row = *rows.contact[a];
    slots_[a] = cache_.slot({kContactRow, rows.contact_key[a / d], a % d}, row.index.data(), row.value.data(), row.count);
  }
  for (int e = 0; e < ne; ++e) slots_[nc + e] = equality_slot(*rows.equalities, e);
  for (int i = 0; i < rows.tie_rows(); ++i) {
    const SparseRow& row = (*rows.ties)[i];
    slots_[nc + ne + i] = cache_.slot({kTieRow, {}, i}, row.index.data(), row.value.data(), row.count);
  }
  cache_.finish();
}

bool ForwardColumnsOperator::sparse_delassus(const ProblemRows& rows, SparseDelassus& W, bool forced) {
  const int m = rows.size();
  if ((!forced && m < kSparseRows) || rows.equality_rows() + rows.tie_rows() > 0) return false;
  take_slots(rows);
  // The same rows with the same forward columns as the W stored last (a pile at rest): W holds.
  if (W.rows() == m && cache_.still_holds(sparse_taken_, slots_)) return true;
  columns_.resize(m);
  for (int a = 0; a < m; ++a) columns_[a] = &cache_.forward(slots_[a]);
  slots_taken_ = !block_gram_.assemble(operators_.sparse_factor(), columns_, rows.dimension,
                                       rows.contact_rows() / rows.dimension, W, forced ? 1.0 : kSparseDensity);
  if (slots_taken_) sparse_taken_ = {};  // declined: W_sparse was not formed from these slots
  return !slots_taken_;
}

void ForwardColumnsOperator::delassus(const ProblemRows& rows, Matrix& W) {
  const int m = rows.size();
  if (!slots_taken_) take_slots(rows);
  slots_taken_ = false;
  cache_.compute_entries();
  if (W.rows() == m && W.cols() == m && cache_.still_holds(copied_, slots_)) return;
  W.resize(m, m);
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) W(a, b) = cache_(slots_[a], slots_[b]);
}

void ForwardColumnsOperator::add_response(const ProblemRows& rows, const Vector& r, Vector& v) {
  if (rows.size() == 0) return;
  const SparseLdlt& factor = operators_.sparse_factor();
  sum_.setZero(factor.size());
  for (int a = 0; a < rows.size(); ++a) SparseLdlt::add_scaled(r(a), cache_.forward(slots_[a]), sum_);
  factor.back_substitute(sum_, work_);
  v += work_;
}

void ForwardColumnsOperator::forward_half(const Vector& f) {
  operators_.sparse_factor().forward_substitute(f, free_forward_, free_scaled_);
}

void ForwardColumnsOperator::gather_candidates(const std::vector<ActiveContact>& contacts,
                                               const std::vector<SparseRow>& rows, int dimension,
                                               const Matrix* equalities) {
  halves_ = true;
  const int candidates = static_cast<int>(contacts.size());
  const int ne = equalities ? static_cast<int>(equalities->rows()) : 0;
  candidate_slots_.resize(dimension * candidates + ne);
  cache_.begin(operators_.sparse_factor());
  for (int i = 0; i < candidates; ++i)
    for (int k = 0; k < dimension; ++k) {
      const SparseRow& row = rows[dimension * i + k];
      candidate_slots_[dimension * i + k] =
          cache_.slot({kContactRow, contacts[i].point.key, k}, row.index.data(), row.value.data(), row.count);
    }
  for (int e = 0; e < ne; ++e) candidate_slots_[dimension * candidates + e] = equality_slot(*equalities, e);
  cache_.finish();
  forward_rows_.assign(cache_, candidate_slots_, operators_.sparse_factor().size());
  forward_rows_.dots(free_scaled_, candidate_dots_);
}

void ForwardColumnsOperator::free_velocity(const Vector& v_k, Vector& v) const {
  operators_.sparse_factor().back_substitute(free_forward_, v);
  v += v_k;
}

void ForwardColumnsOperator::velocity(const ProblemRows& rows, const Vector& r, const Vector& v_k, Vector& v) {
  sum_ = free_forward_;
  candidate_impulses_.assign(forward_rows_.columns(), 0.0);
  candidate_in_problem_.assign(forward_rows_.columns(), 0);
  for (int a = 0; a < rows.size(); ++a) {
    const int c = rows.candidate_row(a);
    candidate_impulses_[c] = r(a);
    candidate_in_problem_[c] = 1;
  }
  forward_rows_.add(candidate_impulses_, candidate_in_problem_, sum_);
  operators_.sparse_factor().back_substitute(sum_, work_);
  v = v_k + work_;
}

}  // namespace csim
