#include "engine/steppers/generalized_alpha_response.h"

#include <algorithm>

namespace csim {

const GeneralizedAlphaResponse::Columns& GeneralizedAlphaResponse::columns(const Key& key, const SparseRow& row) {
  Columns& col = columns_[key];
  col.used = true;
  if (col.factorization == operators_.factorizations() && col.row == row) return col;
  const double h = step_;
  const GeneralizedAlphaCoefficients& k = coefficients_;
  const double c = h * h * k.acceleration_weight() * (k.beta - 0.5 * k.gamma);
  col.row = row;
  col.factorization = operators_.factorizations();
  col.Z.setZero(operators_.size());
  row.scatter(1.0, col.Z);
  col.G = col.Z;
  mass_.solve_in_place(col.Z);
  if (operators_.has_stiffness() && c > 0.0) {
    operators_.apply_stiffness(col.Z, work_);
    col.G += c * work_;
  }
  operators_.solve_in_place(col.G);
  col.reach.clear();
  for (int i = 0; i < col.G.size(); ++i)
    if (col.G(i) != 0.0) col.reach.push_back(i);
  const std::size_t solved = col.reach.size();
  for (int e = 0; e < row.count; ++e)  // h's own unknowns, where G may vanish (ascending: a bisection)
    if (!std::binary_search(col.reach.begin(), col.reach.begin() + solved, row.index[e]))
      col.reach.push_back(row.index[e]);
  return col;
}

void GeneralizedAlphaResponse::take_columns(const ProblemRows& rows) {
  const int m = rows.contact_rows();  // the stepper has no equality or tie rows (generalized_alpha.h)
  const int d = rows.dimension;
  row_columns_.resize(m);
  for (auto& entry : columns_) entry.second.used = false;
  for (int a = 0; a < m; ++a) row_columns_[a] = &columns({rows.contact_key[a / d], a % d}, *rows.contact[a]);
  std::erase_if(columns_, [](const auto& entry) { return !entry.second.used; });
}

bool GeneralizedAlphaResponse::sparse_delassus(const ProblemRows& rows, SparseDelassus& W, bool forced) {
  const int m = rows.contact_rows();
  if ((!forced && m < kSparseRows) || rows.equality_rows() + rows.tie_rows() > 0) return false;
  take_columns(rows);
  reach_.resize(m);
  for (int a = 0; a < m; ++a) reach_[a] = &row_columns_[a]->reach;
  if (!pattern_.build(operators_.size(), reach_, rows.dimension, m / rows.dimension, forced ? 1.0 : kSparseDensity))
    return false;
  pattern_.fill(W, [&](int a, int b) {
    return a == b ? rows.dot(a, row_columns_[a]->G)
                  : 0.5 * (rows.dot(b, row_columns_[a]->G) + rows.dot(a, row_columns_[b]->G));
  });
  return true;
}

void GeneralizedAlphaResponse::delassus(const ProblemRows& rows, Matrix& W) {
  const int m = rows.contact_rows();
  take_columns(rows);
  W.resize(m, m);
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) W(a, b) = rows.dot(a, row_columns_[b]->G);
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < a; ++b) W(a, b) = W(b, a) = 0.5 * (W(a, b) + W(b, a));
}

void GeneralizedAlphaResponse::add_response(const ProblemRows& rows, const Vector& r, Vector& v) {
  for (int a = 0; a < rows.contact_rows(); ++a)
    if (r(a) != 0.0) v += r(a) * row_columns_[a]->G;
}

void GeneralizedAlphaResponse::add_jumps(const Vector& r, Vector& v, Vector& q, Vector& w) const {
  const double h = step_;
  const GeneralizedAlphaCoefficients& k = coefficients_;
  const double cw = k.acceleration_weight();
  for (int a = 0; a < static_cast<int>(row_columns_.size()); ++a) {
    if (r(a) == 0.0) continue;
    const Columns& col = *row_columns_[a];
    v += r(a) * col.G;
    q += (r(a) * h * k.beta / k.gamma) * col.G + (r(a) * h * (0.5 - k.beta / k.gamma)) * col.Z;
    w += (r(a) / (h * k.gamma * cw)) * (col.G - col.Z);
  }
}

}  // namespace csim
