#include "engine/contact_stage/body_block_operator.h"

#include "engine/structural_operators.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <stdexcept>

namespace csim {

BodyBlockOperator::BodyBlockOperator(const StructuralOperators& operators) {
  const World& world = operators.world();
  const SparseMatrix& mass = operators.mass();
  body_of_.assign(static_cast<std::size_t>(world.velocity_size), -1);
  for (const BodyInstance& instance : world.bodies) {
    BodyFactor factor;
    factor.offset = instance.velocity_offset;
    factor.size = instance.body->velocity_size();
    if (factor.size > 0) {
      const Matrix block = Matrix(mass.block(factor.offset, factor.offset, factor.size, factor.size));
      const Eigen::LLT<Matrix> llt(block);
      if (llt.info() != Eigen::Success)
        throw std::invalid_argument("BodyBlockOperator: body '" + instance.name + "' has a mass block that is not positive definite");
      const Matrix upper = llt.matrixU();  // Lᵀ
      const Matrix inverse = upper.triangularView<Eigen::Upper>().solve(Matrix::Identity(factor.size, factor.size));
      factor.inverse_factor_transpose.topLeftCorner(factor.size, factor.size) = inverse;
      factor.diagonal = inverse.isDiagonal(0.0);
      for (int k = 0; k < factor.size; ++k) body_of_[factor.offset + k] = static_cast<int>(bodies_.size());
    }
    bodies_.push_back(factor);
  }
  factors_.bodies = static_cast<int>(bodies_.size());
  contacts_of_.resize(bodies_.size());
}

void BodyBlockOperator::scale_rows(const ProblemRows& rows) {
  const int D = dimension_ = rows.dimension;
  const int contacts = rows.contact_rows() / D;
  factors_.body.resize(contacts);
  factors_.scaled_rows.resize(static_cast<std::size_t>(2 * contacts) * D * kBody);
  using Rows = Eigen::Matrix<double, 3, kBody, Eigen::RowMajor>;  // D ≤ 3 rows used
  for (int c = 0; c < contacts; ++c) {
    // The contact's bodies, ascending, and its rows on each.
    std::array<int, 2>& pair = factors_.body[c];
    pair = {-1, -1};
    Rows H[2] = {Rows::Zero(), Rows::Zero()};
    for (int k = 0; k < D; ++k) {
      const SparseRow& row = *rows.contact[D * c + k];
      for (int e = 0; e < row.count; ++e) {
        const int b = body_of_[row.index[e]];
        if (b < 0) continue;
        int side = b == pair[0] ? 0 : b == pair[1] ? 1 : -1;
        if (side < 0) {
          if (pair[1] >= 0) throw std::logic_error("BodyBlockOperator: a contact row moves more than two bodies");
          side = pair[0] < 0 ? 0 : 1;
          pair[side] = b;
        }
        H[side](k, row.index[e] - bodies_[b].offset) += row.value[e];
      }
    }
    if (pair[1] >= 0 && pair[1] < pair[0]) {
      std::swap(pair[0], pair[1]);
      std::swap(H[0], H[1]);
    }
    for (int side = 0; side < 2; ++side) {
      double* K = factors_.scaled_rows.data() + static_cast<std::size_t>(2 * c + side) * D * kBody;
      const int b = pair[side];
      if (b < 0) {
        std::fill(K, K + D * kBody, 0.0);
        continue;
      }
      const BodyFactor& body = bodies_[b];
      Rows scaled;
      if (body.diagonal) scaled = H[side] * body.inverse_factor_transpose.diagonal().asDiagonal();
      else scaled.noalias() = H[side] * body.inverse_factor_transpose;
      std::copy(scaled.data(), scaled.data() + D * kBody, K);
    }
  }
}

template <int D>
void BodyBlockOperator::block(int c, int d, double* out) const {
  for (int e = 0; e < D * D; ++e) out[e] = 0.0;
  const std::array<int, 2>& a = factors_.body[c];
  const std::array<int, 2>& b = factors_.body[d];
  for (int s = 0; s < 2; ++s) {  // a's bodies ascending, so the shared ones are summed in ascending order
    if (a[s] < 0) continue;
    const int t = b[0] == a[s] ? 0 : b[1] == a[s] ? 1 : -1;
    if (t < 0) continue;
    const double* K_c = factors_.scaled_rows.data() + static_cast<std::size_t>(2 * c + s) * D * kBody;
    const double* K_d = factors_.scaled_rows.data() + static_cast<std::size_t>(2 * d + t) * D * kBody;
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) {
        double sum = 0.0;
        for (int k = 0; k < kBody; ++k) sum += K_c[kBody * i + k] * K_d[kBody * j + k];
        out[D * i + j] += sum;
      }
  }
}

void BodyBlockOperator::apply_inverse(Vector& x) const {
  using Body = Eigen::Matrix<double, kBody, 1>;
  for (const BodyFactor& body : bodies_) {
    if (body.size == 0) continue;
    Body y = Body::Zero();
    y.head(body.size) = x.segment(body.offset, body.size);
    if (body.diagonal) {
      y = y.cwiseProduct(body.inverse_factor_transpose.diagonal().cwiseAbs2());
    } else {
      const Body scaled = body.inverse_factor_transpose.transpose() * y;
      y.noalias() = body.inverse_factor_transpose * scaled;
    }
    x.segment(body.offset, body.size) = y.head(body.size);
  }
}

void BodyBlockOperator::forward_half(const Vector& f) {
  free_change_ = f;
  apply_inverse(free_change_);
}

void BodyBlockOperator::gather_candidates(const std::vector<ActiveContact>& candidates,
                                          const std::vector<SparseRow>& rows, int dimension, const Matrix* equalities) {
  const int count = dimension * static_cast<int>(candidates.size());
  const int ne = equalities ? static_cast<int>(equalities->rows()) : 0;
  candidate_dots_.resize(static_cast<std::size_t>(count + ne));
  for (int c = 0; c < count; ++c) candidate_dots_[c] = rows[c].dot(free_change_);
  for (int e = 0; e < ne; ++e) candidate_dots_[count + e] = equalities->row(e).dot(free_change_);
}

void BodyBlockOperator::velocity(const ProblemRows& rows, const Vector& r, const Vector& v_k, Vector& v) {
  v = v_k + free_change_;
  add_response(rows, r, v);
}

void BodyBlockOperator::delassus(const ProblemRows& rows, Matrix& W) {
  scale_rows(rows);
  const int D = dimension_, m = rows.size(), nc = rows.contact_rows(), contacts = nc / D;
  W.setZero(m, m);
  double block_values[9];
  for (int c = 0; c < contacts; ++c)
    for (int d = c; d < contacts; ++d) {
      if (D == 2) block<2>(c, d, block_values);
      else block<3>(c, d, block_values);
      for (int i = 0; i < D; ++i)
        for (int j = 0; j < D; ++j) {
          W(D * c + i, D * d + j) = block_values[D * i + j];
          W(D * d + j, D * c + i) = block_values[D * i + j];
        }
    }
  equality_columns_.resize(m - nc);
  for (int a = nc; a < m; ++a) {
    Vector& column = equality_columns_[a - nc];
    column.setZero(static_cast<Eigen::Index>(body_of_.size()));
    rows.scatter(a, 1.0, column);
    apply_inverse(column);
    for (int b = 0; b <= a; ++b) W(a, b) = W(b, a) = rows.dot(b, column);
  }
}

bool BodyBlockOperator::sparse_delassus(const ProblemRows& rows, SparseDelassus& W, bool forced) {
  if (rows.equality_rows() + rows.tie_rows() > 0) return false;
  const int D = rows.dimension, m = rows.size(), contacts = m / D;
  if (!forced && m < kSparseRows) return false;
  scale_rows(rows);
  for (std::vector<int>& list : contacts_of_) list.clear();
  for (int c = 0; c < contacts; ++c)
    for (const int b : factors_.body[c])
      if (b >= 0) contacts_of_[b].push_back(c);
  if (!forced)
    for (const std::vector<int>& list : contacts_of_)
      if (static_cast<double>(list.size()) > kSparseDensity * contacts) return false;
  // Compressed rows by whole blocks: contact c's D rows hold the same columns, its neighbours' (itself
  // included) ascending.
  std::vector<int> starts(contacts + 1, 0);
  std::vector<int> neighbours;
  neighbours.reserve(static_cast<std::size_t>(contacts) * 8);
  for (int c = 0; c < contacts; ++c) {
    starts[c] = static_cast<int>(neighbours.size());
    const std::array<int, 2>& pair = factors_.body[c];
    const std::vector<int>* first = pair[0] >= 0 ? &contacts_of_[pair[0]] : nullptr;
    const std::vector<int>* second = pair[1] >= 0 ? &contacts_of_[pair[1]] : nullptr;
    if (first && second) std::set_union(first->begin(), first->end(), second->begin(), second->end(), std::back_inserter(neighbours));
    else if (first) neighbours.insert(neighbours.end(), first->begin(), first->end());
    else if (second) neighbours.insert(neighbours.end(), second->begin(), second->end());
    else neighbours.push_back(c);  // a contact on fixed bodies alone: its zero diagonal block
  }
  starts[contacts] = static_cast<int>(neighbours.size());
  const long entries = static_cast<long>(neighbours.size()) * D * D;
  W.resize(m, m);
  W.resizeNonZeros(entries);
  int* outer = W.outerIndexPtr();
  int* inner = W.innerIndexPtr();
  double* value = W.valuePtr();
  double block_values[9];
  long position = 0;
  for (int c = 0; c < contacts; ++c) {
    const int width = D * (starts[c + 1] - starts[c]);
    for (int i = 0; i < D; ++i) outer[D * c + i] = static_cast<int>(position + static_cast<long>(i) * width);
    for (int n = starts[c]; n < starts[c + 1]; ++n) {
      const int d = neighbours[n];
      if (d >= c) {
        if (D == 2) block<2>(c, d, block_values);
        else block<3>(c, d, block_values);
      } else {  // block (d, c), stored already, transposed: the same bits as forming (c, d) (header)
        const auto begin = neighbours.begin() + starts[d], end = neighbours.begin() + starts[d + 1];
        const long at_d = outer[D * d] + static_cast<long>(D) * (std::lower_bound(begin, end, c) - begin);
        const long width_d = static_cast<long>(D) * (starts[d + 1] - starts[d]);
        for (int i = 0; i < D; ++i)
          for (int j = 0; j < D; ++j) block_values[D * i + j] = value[at_d + j * width_d + i];
      }
      const long column_offset = static_cast<long>(D) * (n - starts[c]);
      for (int i = 0; i < D; ++i)
        for (int j = 0; j < D; ++j) {
          const long at = position + static_cast<long>(i) * width + column_offset + j;
          inner[at] = D * d + j;
          value[at] = block_values[D * i + j];
        }
    }
    position += static_cast<long>(D) * width;
  }
  outer[m] = static_cast<int>(position);
  return true;
}

bool BodyBlockOperator::body_blocks(BodyBlockDelassus& blocks) const {
  blocks.bodies = factors_.bodies;
  blocks.body = factors_.body;
  blocks.scaled_rows = factors_.scaled_rows;
  return true;
}

void BodyBlockOperator::add_response(const ProblemRows& rows, const Vector& r, Vector& v) {
  const int D = dimension_, nc = rows.contact_rows(), contacts = nc / D;
  w_.setZero(static_cast<Eigen::Index>(kBody) * static_cast<Eigen::Index>(bodies_.size()));
  for (int c = 0; c < contacts; ++c)
    for (int side = 0; side < 2; ++side) {
      const int b = factors_.body[c][side];
      if (b < 0) continue;
      const double* K = factors_.scaled_rows.data() + static_cast<std::size_t>(2 * c + side) * D * kBody;
      for (int k = 0; k < kBody; ++k)
        for (int i = 0; i < D; ++i) w_(kBody * b + k) += K[kBody * i + k] * r(D * c + i);
    }
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const BodyFactor& body = bodies_[b];
    if (body.size == 0) continue;
    v.segment(body.offset, body.size) +=
        body.inverse_factor_transpose.topLeftCorner(body.size, body.size) * w_.segment(kBody * b, body.size);
  }
  for (int a = nc; a < rows.size(); ++a) v += r(a) * equality_columns_[a - nc];
}

}  // namespace csim
