#include "engine/structural_operators.h"

#include "contact/friction_contact_problem.h"
#include "engine/linear_algebra/dense_inverse.h"
#include "engine/linear_algebra/small_dense_products.h"
#include "engine/steppers/proximal.h"
#include "fem/mesh.h"

#include <chrono>

namespace csim {

namespace {

// A sparse expression (sums of scaled matrices) evaluated entry for entry as `SparseMatrix m = expression`
// does, by Eigen's evaluator, but counted first and stored once at its size: the assignment grows its
// storage by doubling, to up to twice the entries (three times while it copies). lower: the entries
// i ≥ j alone.
template <class Expression>
SparseMatrix evaluate_sized(const Expression& expression, bool lower) {
  using Evaluator = Eigen::internal::evaluator<Expression>;
  static_assert(!(Evaluator::Flags & Eigen::RowMajorBit), "column-major expressions only");
  const Evaluator evaluator(expression);
  const int columns = static_cast<int>(expression.cols());
  SparseMatrix result(expression.rows(), columns);
  int* start = result.outerIndexPtr();
  for (int j = 0; j < columns; ++j) {
    int count = 0;
    for (typename Evaluator::InnerIterator it(evaluator, j); it; ++it)
      if (!lower || it.index() >= j) ++count;
    start[j + 1] = start[j] + count;
  }
  result.resizeNonZeros(start[columns]);
  int* row = result.innerIndexPtr();
  double* value = result.valuePtr();
  for (int j = 0, k = 0; j < columns; ++j)
    for (typename Evaluator::InnerIterator it(evaluator, j); it; ++it)
      if (!lower || it.index() >= j) {
        row[k] = static_cast<int>(it.index());
        value[k++] = it.value();
      }
  return result;
}

// True if every body has at most BodyBlockDelassus::kBodySize unknowns and M couples no two bodies.
bool mass_within_bodies(const World& world, const SparseMatrix& mass) {
  std::vector<int> body_of(static_cast<std::size_t>(world.velocity_size), -1);
  for (std::size_t b = 0; b < world.bodies.size(); ++b) {
    const BodyInstance& body = world.bodies[b];
    if (body.body->velocity_size() > BodyBlockDelassus::kBodySize) return false;
    for (int k = 0; k < body.body->velocity_size(); ++k) body_of[body.velocity_offset + k] = static_cast<int>(b);
  }
  for (int j = 0; j < mass.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(mass, j); it; ++it)
      if (it.value() != 0.0 && (body_of[it.row()] < 0 || body_of[it.row()] != body_of[it.col()])) return false;
  return true;
}

}  // namespace

StructuralOperators::StructuralOperators(const Dynamics& dynamics)
    : world_(dynamics.world()), dynamics_(dynamics) {
  const int n = world_.velocity_size;
  sparse_ = n > kDenseLimit;
  has_stiffness_ = dynamics.has_stiffness();
  nonlinear_ = dynamics.nonlinear();
  has_damping_ = dynamics.has_damping();
  explicit_inverse_ = !sparse_ && !dynamics.has_elastic_bodies();
  factored_coordinates_.resize(dynamics.spring_stiffness_coordinates().size());
  if (sparse_ && nonlinear_) body_stiffness_.resize(n, n);  // the tangent, at each update
  else dynamics.body_stiffness().swap(body_stiffness_);  // Eigen 3.4's SparseMatrix has no move: swaps
  block_diagonal_ = sparse_ && !has_stiffness_ && !has_damping_ && !nonlinear_ && !dynamics.has_elastic_bodies() &&
                    mass_within_bodies(world_, dynamics.mass());
  if (!sparse_) {
    dense_mass_ = Matrix(dynamics.mass());
    dense_stiffness_ = Matrix(body_stiffness_);
    dense_damping_ = Matrix(dynamics.damping());
    mass_diagonal_ = explicit_inverse_ && is_diagonal(dense_mass_);
    if (mass_diagonal_) mass_diagonal_entries_ = dense_mass_.diagonal();
  }
}

// K(q) of a linear World is a function of the springs' orientation coordinates alone
// (Dynamics::spring_stiffness_coordinates): when they and A's coefficients are what A was factored
// with, A is the same to the bit and is kept (a shoe that slides without turning keeps its factorization).
bool StructuralOperators::factored_for(const Vector& q, double damping_coefficient, double stiffness_coefficient) const {
  if (!factored_ || nonlinear_ || damping_coefficient != factored_damping_ || stiffness_coefficient != factored_stiffness_)
    return false;
  const std::vector<int>& coordinates = dynamics_.spring_stiffness_coordinates();
  for (std::size_t i = 0; i < coordinates.size(); ++i)
    if (q(coordinates[i]) != factored_coordinates_[i]) return false;
  return true;
}

void StructuralOperators::update_coefficients(const Vector& q, double damping_coefficient, double stiffness_coefficient) {
  if (factored_for(q, damping_coefficient, stiffness_coefficient)) return;
  // A is a function of K and its coefficients, and the springs' K of their Jacobian columns: a body
  // that turned by round-off alone (a shoe held flat by its contacts turns by 1e-25 rad) has the same
  // columns to the bit, and a dense A and its inverse are kept. The columns at q come from the springs'
  // evaluation there, which the step's forces at q made (springs.h).
  const bool compare_columns = compares_columns();
  if (compare_columns && factored_ && damping_coefficient == factored_damping_ &&
      stiffness_coefficient == factored_stiffness_ && dynamics_.same_spring_jacobian_columns(q, factored_spring_columns_)) {
    for (std::size_t i = 0; i < factored_coordinates_.size(); ++i)
      factored_coordinates_[i] = q(dynamics_.spring_stiffness_coordinates()[i]);
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  const double scale = stiffness_coefficient;
  if (nonlinear_) {  // the bodies' tangent at q (a linear body's K is its tangent)
    Triplets tangent;
    dynamics_.add_body_stiffness(q, tangent);
    body_stiffness_.setFromTriplets(tangent.begin(), tangent.end());
    if (!sparse_) dense_stiffness_ = Matrix(body_stiffness_);
  }
  if (sparse_) {
    if (dynamics_.has_springs() && !(dynamics_.constant_stiffness() && factored_)) {  // a constant sum is formed once
      Triplets springs;
      dynamics_.add_spring_stiffness(q, springs);
      SparseMatrix spring_matrix(world_.velocity_size, world_.velocity_size);
      spring_matrix.setFromTriplets(springs.begin(), springs.end());
      evaluate_sized(body_stiffness_ + spring_matrix, false).swap(sparse_stiffness_);
      if (dynamics_.constant_stiffness()) SparseMatrix().swap(body_stiffness_);  // freed (an assignment keeps the storage)
    }
    // CHOLMOD reads A's lower triangle only (sparse_ldlt.h): the upper one is not formed.
    const SparseMatrix A =
        evaluate_sized(dynamics_.mass() + damping_coefficient * dynamics_.damping() + scale * stiffness(), true);
    // The symbolic analysis depends only on the pattern, which K's refresh keeps (sparse_ldlt.h).
    if (nonlinear_) factor_regularized(A);
    else sparse_factor_.factor_positive_definite(A);
    // A constant A is factored once: the map kept for refactorizations goes (10 MB at 52k DOFs).
    if (!nonlinear_ && dynamics_.constant_stiffness()) sparse_factor_.release_pattern();
  } else {
    if (dynamics_.has_springs()) {
      dynamics_.spring_stiffness(q, dense_stiffness_);
      if (body_stiffness_.nonZeros() > 0) dense_stiffness_ += body_stiffness_;
    }
    Matrix& A = dense_iteration_;  // a member: no allocation once sized
    A = dense_mass_;
    if (has_damping_) A += damping_coefficient * dense_damping_;
    A += scale * dense_stiffness_;
    factor_dense(A);
  }
  factored_ = true;
  if (compare_columns) dynamics_.spring_jacobian_columns(q, factored_spring_columns_);
  for (std::size_t i = 0; i < factored_coordinates_.size(); ++i)
    factored_coordinates_[i] = q(dynamics_.spring_stiffness_coordinates()[i]);
  ++factorizations_;
  factored_damping_ = damping_coefficient;
  factored_stiffness_ = stiffness_coefficient;
  factorization_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A lumped World's A (masses and springs: mass-dominated, well conditioned) is inverted
// (dense_inverse.h); one that is not positive definite (springs whose geometric stiffness outweighs
// the masses) through a pivoting LDLᵀ. A small elastic body's A is factored: h²K can make it
// ill-conditioned, and an explicit inverse then loses digits that the factorization's solves keep
// (fe-damped-drift's elastic energy moved by a quarter). A nonlinear World's indefinite A gets the
// proximal term of the header.
void StructuralOperators::factor_dense(const Matrix& A) {
  if (explicit_inverse_) {
    if (!invert_positive_definite(A, dense_scratch_, dense_inverse_)) {
      dense_factor_.compute(A);
      dense_inverse_ = dense_factor_.solve(Matrix::Identity(A.rows(), A.cols()));
    }
    inverse_diagonal_ = is_diagonal(dense_inverse_);
    if (inverse_diagonal_) inverse_diagonal_entries_ = dense_inverse_.diagonal();
    return;
  }
  dense_factor_.compute(A);
  if (nonlinear_ && !(dense_factor_.vectorD().array() > 0.0).all()) {
    const Matrix identity = Matrix::Identity(A.rows(), A.cols());
    regularize(A.diagonal().cwiseAbs().maxCoeff(), [&](double epsilon) {
      dense_factor_.compute(A + epsilon * identity);
      return (dense_factor_.vectorD().array() > 0.0).all();
    });
  }
}

// A (or A + ε I, see the header) into sparse_factor_.
void StructuralOperators::factor_regularized(const SparseMatrix& A) {
  auto positive_definite = [&](const SparseMatrix& A) { return sparse_factor_.factor_positive_definite(A); };
  if (positive_definite(A)) return;
  SparseMatrix identity(A.rows(), A.cols());
  identity.setIdentity();
  regularize(A.diagonal().cwiseAbs().maxCoeff(),
             [&](double epsilon) { return positive_definite(A + epsilon * identity); });
}

// The proximal term of the header (engine/steppers/proximal.h), counted; FemError when it fails.
template <class PositiveDefiniteWith>
void StructuralOperators::regularize(double largest, PositiveDefiniteWith&& positive_definite_with) {
  if (!grow_proximal_term(largest, positive_definite_with))
    throw FemError("the iteration matrix stays indefinite (a material instability?)");
  ++regularizations_;
}

void StructuralOperators::solve_in_place(Vector& x) const {
  if (sparse_) sparse_factor_.solve_in_place(x);
  else if (explicit_inverse_) {
    if (inverse_diagonal_) small_diagonal_multiply(inverse_diagonal_entries_, x, dense_solution_);
    else small_multiply(dense_inverse_, x, dense_solution_);
    x = dense_solution_;
  } else {
    dense_factor_.solveInPlace(x);
  }
}

void StructuralOperators::dense_columns(const Matrix& Ht, Matrix& G) const {
  if (inverse_diagonal_) small_diagonal_columns(inverse_diagonal_entries_, Ht, G);
  else small_combine_columns(dense_inverse_, Ht, G);
}

// A lumped World's products are compiled for its size (small_dense_products.h); a small elastic World
// keeps Eigen's, whose summation order its results were verified with.
void StructuralOperators::apply_mass(const Vector& v, Vector& out) const {
  if (sparse_) out.noalias() = dynamics_.mass() * v;
  else if (mass_diagonal_) small_diagonal_multiply(mass_diagonal_entries_, v, out);
  else if (explicit_inverse_) small_multiply(dense_mass_, v, out);
  else out.noalias() = dense_mass_ * v;
}

double StructuralOperators::kinetic_energy(const Vector& v, const Vector& x, Vector& Mx) const {
  if (sparse_) return dynamics_.kinetic_energy(v, x, Mx);
  double kinetic = 0.0;
  if (mass_diagonal_) {
    small_diagonal_multiply(mass_diagonal_entries_, v, Mx);  // M v, Mx as scratch
    kinetic = 0.5 * v.dot(Mx);
  } else {
    kinetic = dynamics_.kinetic_energy(v);
  }
  apply_mass(x, Mx);
  return kinetic;
}

double StructuralOperators::kinetic_energy(const Vector& v, Vector& scratch) const {
  if (sparse_ || !mass_diagonal_) return dynamics_.kinetic_energy(v);
  small_diagonal_multiply(mass_diagonal_entries_, v, scratch);
  return 0.5 * v.dot(scratch);
}

void StructuralOperators::apply_damping(const Vector& v, Vector& out) const {
  if (sparse_) out.noalias() = dynamics_.damping() * v;
  else if (explicit_inverse_) small_multiply(dense_damping_, v, out);
  else out.noalias() = dense_damping_ * v;
}

void StructuralOperators::apply_stiffness(const Vector& v, Vector& out) const {
  if (sparse_) out.noalias() = stiffness() * v;
  else if (explicit_inverse_) small_multiply(dense_stiffness_, v, out);
  else out.noalias() = dense_stiffness_ * v;
}

}  // namespace csim
