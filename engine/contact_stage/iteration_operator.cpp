#include "engine/contact_stage/iteration_operator.h"

#include "engine/contact_stage/body_block_operator.h"
#include "engine/contact_stage/forward_columns.h"
#include "engine/linear_algebra/small_dense_products.h"
#include "engine/structural_operators.h"

namespace csim {

namespace {

// A lumped World's A⁻¹, kept (dense_inverse.h): G = A⁻¹ Hᵀ and W = H G by products compiled for the
// World's size (small_dense_products.h), Hᵀ dense (n × m, a dozen rows of a few unknowns).
class DenseInverseOperator final : public IterationOperator {
 public:
  explicit DenseInverseOperator(const StructuralOperators& operators) : operators_(operators) {}
  void delassus(const ProblemRows& rows, Matrix& W) override {
    const int m = rows.size();
    transposed_rows_.setZero(operators_.size(), m);
    for (int a = 0; a < rows.contact_rows(); ++a) {  // a contact row's distinct entries, written
      const SparseRow& row = *rows.contact[a];
      double* column = transposed_rows_.col(a).data();
      for (int k = 0; k < row.count; ++k) column[row.index[k]] = row.value[k];
    }
    for (int a = rows.contact_rows(); a < m; ++a) rows.scatter(a, 1.0, transposed_rows_.col(a));
    operators_.dense_columns(transposed_rows_, columns_);
    small_symmetric_gram(transposed_rows_, columns_, W);
  }
  void add_response(const ProblemRows&, const Vector& r, Vector& v) override { small_add_columns(columns_, r, v); }
  // Dense dots of n entries, a few instructions each at the compiled sizes.
  void apply_rows(const ProblemRows&, const Vector& v, Vector& u) const override {
    small_transpose_multiply(transposed_rows_, v, u);
  }

 private:
  const StructuralOperators& operators_;
  Matrix transposed_rows_, columns_;  // Hᵀ and G = A⁻¹ Hᵀ
};

// A small elastic World's dense LDLᵀ of A: a column A⁻¹ hᵀ a row (a column costs less than keeping it).
class SolvedColumnsOperator final : public IterationOperator {
 public:
  explicit SolvedColumnsOperator(const StructuralOperators& operators) : operators_(operators) {}
  void delassus(const ProblemRows& rows, Matrix& W) override {
    const int m = rows.size();
    columns_.resize(m);
    for (int a = 0; a < m; ++a) {
      columns_[a].setZero(operators_.size());
      rows.scatter(a, 1.0, columns_[a]);
      operators_.solve_in_place(columns_[a]);
    }
    W.resize(m, m);
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b) W(a, b) = rows.dot(a, columns_[b]);
  }
  void add_response(const ProblemRows& rows, const Vector& r, Vector& v) override {
    for (int a = 0; a < rows.size(); ++a) v += r(a) * columns_[a];
  }

 private:
  const StructuralOperators& operators_;
  std::vector<Vector> columns_;
};

// A sparse A refactored at every Newton iterate (finite strain): no column is kept, W comes from the
// forward substitution alone (SparseLdlt::delassus), and A⁻¹ (Hᵀ r) is one solve.
class DirectOperator final : public IterationOperator {
 public:
  explicit DirectOperator(StructuralOperators& operators) : operators_(operators) {}
  void delassus(const ProblemRows& rows, Matrix& W) override {
    const int m = rows.size();
    dense_rows_.setZero(m, operators_.size());
    for (int a = 0; a < m; ++a) rows.scatter(a, 1.0, dense_rows_.row(a));
    W.resize(m, m);
    operators_.delassus(dense_rows_, W);
  }
  void add_response(const ProblemRows& rows, const Vector& r, Vector& v) override {
    if (rows.size() == 0) return;
    work_.setZero(operators_.size());
    for (int a = 0; a < rows.size(); ++a) rows.scatter(a, r(a), work_);
    operators_.solve_in_place(work_);
    v += work_;
  }

 private:
  StructuralOperators& operators_;
  Matrix dense_rows_;  // H, m × n
  Vector work_;
};

}  // namespace

std::unique_ptr<IterationOperator> make_iteration_operator(StructuralOperators& operators) {
  if (operators.explicit_inverse()) return std::make_unique<DenseInverseOperator>(operators);
  if (operators.direct_delassus()) return std::make_unique<DirectOperator>(operators);
  if (operators.block_diagonal()) return std::make_unique<BodyBlockOperator>(operators);
  if (operators.sparse()) return std::make_unique<ForwardColumnsOperator>(operators);
  return std::make_unique<SolvedColumnsOperator>(operators);
}

}  // namespace csim
