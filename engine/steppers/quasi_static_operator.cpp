#include "engine/steppers/quasi_static_operator.h"

namespace csim {

void QuasiStaticOperator::gather(const ProblemRows& rows) {
  const int m = rows.size(), nz = static_cast<int>(T_.cols());
  // H_ is zero but for the entries the last gather wrote: those are cleared, not all m × nz.
  if (H_.rows() == m && H_.cols() == nz)
    for (Eigen::Index entry : H_written_) H_.data()[entry] = 0.0;
  else
    H_.setZero(m, nz);
  H_written_.clear();
  // H_z = H T, row by row through the rows of T.
  for (int a = 0; a < m; ++a) {
    const SparseRow& row = *rows.contact[a];
    for (int k = 0; k < row.count; ++k)
      for (SparseRowMatrix::InnerIterator it(T_, row.index[k]); it; ++it) {
        H_(a, it.col()) += row.value[k] * it.value();
        H_written_.push_back(a + it.col() * m);  // column-major
      }
  }
}

void QuasiStaticOperator::delassus(const ProblemRows&, Matrix& W) { factor_.delassus(H_, W); }

void QuasiStaticOperator::add_response(const ProblemRows&, const Vector& r, Vector& v) {
  if (r.size() == 0) return;
  work_.noalias() = H_.transpose() * r;
  factor_.solve_in_place(work_);
  v += work_;
}

}  // namespace csim
