#include "engine/linear_algebra/linear_products.h"

#include <stdexcept>

namespace csim {

LinearProducts::LinearProducts(std::vector<StiffnessBlock> K, const SparseMatrix& M)
    : stiffness_(std::move(K)), mass_(&M) {
  const Eigen::Index n = M.rows();
  if (M.cols() != n || !M.isCompressed()) throw std::invalid_argument("LinearProducts: M must be square and compressed");
  Eigen::Index end = 0;
  for (const StiffnessBlock& block : stiffness_) {
    const SparseMatrix& A = *block.stiffness;
    if (block.offset < end || A.rows() != A.cols() || block.offset + A.cols() > n || !A.isCompressed())
      throw std::invalid_argument("LinearProducts: a stiffness block outside M, overlapping, or not compressed");
    end = block.offset + A.cols();
  }
}

template <bool WithDv>
void LinearProducts::multiply_columns(const double* q, const double* v, const double* dv, double* Kq, double* Kv,
                                      double* Mv, double* Mdv) const {
  const int* m_start = mass_->outerIndexPtr();
  const int* m_row = mass_->innerIndexPtr();
  const double* m_value = mass_->valuePtr();
  std::size_t block = 0;
  for (int j = 0; j < size(); ++j) {
    while (block < stiffness_.size() && j >= stiffness_[block].offset + stiffness_[block].stiffness->cols()) ++block;
    const double vj = v[j];
    if (block < stiffness_.size() && j >= stiffness_[block].offset) {
      const SparseMatrix& K = *stiffness_[block].stiffness;
      const int offset = stiffness_[block].offset, column = j - offset;
      const double qj = q[stiffness_[block].position_offset + column];
      const int* row = K.innerIndexPtr();
      const double* value = K.valuePtr();
      double* Kq_block = Kq + offset;
      double* Kv_block = Kv + offset;
      for (int p = K.outerIndexPtr()[column]; p < K.outerIndexPtr()[column + 1]; ++p) {
        Kq_block[row[p]] += value[p] * qj;
        Kv_block[row[p]] += value[p] * vj;
      }
    }
    const double dvj = WithDv ? dv[j] : 0.0;
    for (int p = m_start[j]; p < m_start[j + 1]; ++p) {
      Mv[m_row[p]] += m_value[p] * vj;
      if constexpr (WithDv) Mdv[m_row[p]] += m_value[p] * dvj;
    }
  }
}

void LinearProducts::multiply(const Vector& q, const Vector& v, const Vector* dv, Vector& Kq, Vector& Kv,
                              Vector& Mv, Vector* Mdv) const {
  const int n = size();
  Kq.setZero(n);
  Kv.setZero(n);
  Mv.setZero(n);
  if (dv) {
    Mdv->setZero(n);
    multiply_columns<true>(q.data(), v.data(), dv->data(), Kq.data(), Kv.data(), Mv.data(), Mdv->data());
  } else {
    multiply_columns<false>(q.data(), v.data(), nullptr, Kq.data(), Kv.data(), Mv.data(), nullptr);
  }
}

void LinearProducts::multiply_stiffness(const Vector& x, Vector& Kx) const {
  Kx.setZero(size());
  for (const StiffnessBlock& block : stiffness_) {
    const Eigen::Index n = block.stiffness->cols();
    Kx.segment(block.offset, n).noalias() = *block.stiffness * x.segment(block.offset, n);
  }
}

}  // namespace csim
