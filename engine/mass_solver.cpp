#include "engine/mass_solver.h"

#include <stdexcept>

namespace csim {

MassSolver::MassSolver(const Dynamics& dynamics) : sparse_(dynamics.size() > kDenseLimit) {
  bool positive = true;
  if (sparse_) {
    positive = sparse_factor_.factor_positive_definite(dynamics.mass());
  } else if (dynamics.size() > 0) {
    dense_.compute(Matrix(dynamics.mass()));
    positive = dense_.info() == Eigen::Success && (dense_.vectorD().array() > 0.0).all();
  }
  if (!positive) throw std::invalid_argument("the mass matrix is not positive definite (a coordinate without mass)");
}

void MassSolver::solve_in_place(Vector& x) const {
  if (sparse_) sparse_factor_.solve_in_place(x);
  else if (x.size() > 0) dense_.solveInPlace(x);
}

}  // namespace csim
