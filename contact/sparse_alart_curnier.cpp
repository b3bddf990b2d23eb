#include "contact/sparse_alart_curnier.h"

#include <umfpack.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace csim {
namespace {

// UMFPACK's symbolic and numeric objects of one call, freed on every exit.
struct Umfpack {
  void* symbolic = nullptr;
  void* numeric = nullptr;
  double control[UMFPACK_CONTROL];
  double info[UMFPACK_INFO];
  Umfpack() {
    umfpack_di_defaults(control);
    control[UMFPACK_IRSTEP] = 1;  // one step of iterative refinement (the default is two)
  }
  ~Umfpack() {
    if (numeric) umfpack_di_free_numeric(&numeric);
    if (symbolic) umfpack_di_free_symbolic(&symbolic);
  }
  Umfpack(const Umfpack&) = delete;
  Umfpack& operator=(const Umfpack&) = delete;
};

// The Jacobian's assembly per contact: J_c = C_c W_c + E_c (see the header), and F_c.
struct ContactJacobian {
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
};

// F(r), u = W r + b given, and when `jacobian` is given the blocks C_c, E_c.
void evaluate(const FrictionContactProblem& problem, const Eigen::VectorXd& rho, const Eigen::VectorXd& r,
              const Eigen::VectorXd& u, Eigen::VectorXd& F, std::vector<ContactJacobian>* jacobian) {
  const int d = problem.dimension, t = d - 1;
  F.resize(problem.size());
  for (int c = 0; c < problem.contacts; ++c) {
    const Eigen::Index n = static_cast<Eigen::Index>(d) * c;
    const double p = rho(c), mu = problem.mu[c](0);
    ContactJacobian* J = jacobian ? &(*jacobian)[c] : nullptr;
    if (J) J->C.setZero(), J->E.setZero();
    const double a_n = r(n) - p * u(n);
    const bool pressed = a_n > 0.0;
    if (pressed) {
      F(n) = p * u(n);
      if (J) J->C(0, 0) = p;
    } else {
      F(n) = r(n);
      if (J) J->E(0, 0) = 1.0;
    }
    const double R = pressed ? mu * a_n : 0.0;
    Eigen::Vector2d tau = Eigen::Vector2d::Zero();
    for (int k = 0; k < t; ++k) tau(k) = r(n + 1 + k) - p * u(n + 1 + k);
    const double norm = tau.norm();
    if (!(R > 0.0)) {  // open or frictionless: r_t = 0
      for (int k = 0; k < t; ++k) {
        F(n + 1 + k) = r(n + 1 + k);
        if (J) J->E(1 + k, 1 + k) = 1.0;
      }
    } else if (norm <= R) {  // stick: u_t = 0
      for (int k = 0; k < t; ++k) {
        F(n + 1 + k) = p * u(n + 1 + k);
        if (J) J->C(1 + k, 1 + k) = p;
      }
    } else {  // slip: r_t = R τ / |τ|
      const Eigen::Vector2d direction = tau / norm;
      for (int k = 0; k < t; ++k) F(n + 1 + k) = r(n + 1 + k) - R * direction(k);
      if (J) {
        // J_t = −τ̂ ∂R − R (I − τ̂τ̂ᵀ) ∂τ / |τ| + [0 I], with ∂R = μ (e_n − ρ W_n) and ∂τ = [0 I] − ρ W_t.
        for (int k = 0; k < t; ++k) {
          J->C(1 + k, 0) = direction(k) * mu * p;
          J->E(1 + k, 0) = -direction(k) * mu;
          J->E(1 + k, 1 + k) += 1.0;
          for (int j = 0; j < t; ++j) {
            const double projector = (k == j ? 1.0 : 0.0) - direction(k) * direction(j);
            J->C(1 + k, 1 + j) = R / norm * p * projector;
            J->E(1 + k, 1 + j) -= R / norm * projector;
          }
        }
      }
    }
  }
}

// J's values in W's pattern (row block c of W: D rows with the same columns), plus δ on the diagonal.
void assemble(const SparseDelassus& W, int d, const std::vector<ContactJacobian>& jacobian, double delta,
              std::vector<double>& values) {
  const int* outer = W.outerIndexPtr();
  const int* inner = W.innerIndexPtr();
  const double* w = W.valuePtr();
  values.resize(static_cast<std::size_t>(W.nonZeros()));
  for (std::size_t c = 0; c < jacobian.size(); ++c) {
    const int n = d * static_cast<int>(c);
    const ContactJacobian& J = jacobian[c];
    for (int i = 0; i < d; ++i) {
      const int start = outer[n + i], length = outer[n + i + 1] - start;
      for (int pos = 0; pos < length; ++pos) {
        double value = 0.0;
        for (int k = 0; k < d; ++k)
          if (J.C(i, k) != 0.0) value += J.C(i, k) * w[outer[n + k] + pos];
        const int column = inner[start + pos];
        if (column >= n && column < n + d) value += J.E(i, column - n) + (column == n + i ? delta : 0.0);
        values[static_cast<std::size_t>(start + pos)] = value;
      }
    }
  }
}

// y = J x for J in W's pattern with the given values.
void multiply(const SparseDelassus& W, const std::vector<double>& values, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  const int* outer = W.outerIndexPtr();
  const int* inner = W.innerIndexPtr();
  y.resize(W.rows());
  for (Eigen::Index i = 0; i < W.rows(); ++i) {
    double sum = 0.0;
    for (int pos = outer[i]; pos < outer[i + 1]; ++pos) sum += values[static_cast<std::size_t>(pos)] * x(inner[pos]);
    y(i) = sum;
  }
}

}  // namespace

bool sparse_alart_curnier_newton(const FrictionContactProblem& problem, const SparseDelassus& W, Eigen::VectorXd& r,
                                 int max_iterations, double tolerance, double rho_scale, PolishBudget& budget,
                                 NewtonStatistics* statistics) {
  for (int c = 0; c < problem.contacts; ++c)
    if (problem.dimension == 3 && problem.mu[c](0) != problem.mu[c](1)) return false;
  const int d = problem.dimension;
  const Eigen::Index m = problem.size();
  if (m == 0 || r.size() != m || problem.equalities != 0) return false;
  const double product_flops = 2.0 * static_cast<double>(W.nonZeros());

  Eigen::VectorXd rho(problem.contacts);
  for (int c = 0; c < problem.contacts; ++c) {
    double trace = 0.0;
    for (int k = 0; k < d; ++k) trace += W.coeff(d * c + k, d * c + k);
    rho(c) = rho_scale * d / std::max(trace, 1e-300);
  }
  Eigen::VectorXd rho_b = problem.b;
  for (int c = 0; c < problem.contacts; ++c) rho_b.segment(static_cast<Eigen::Index>(d) * c, d) *= rho(c);
  const double scale_b = rho_b.norm();

  // The symbolic analysis (an AMD ordering, about linear in W's entries) is counted as one product.
  if (!budget.allows(2.0 * product_flops)) {
    if (statistics) *statistics = NewtonStatistics{};
    return true;
  }
  budget.spent += product_flops;
  Umfpack lu;
  const int size = static_cast<int>(m);
  // UMFPACK reads compressed columns: W's rows are Wᵀ's columns, and J is solved through its transpose.
  if (umfpack_di_symbolic(size, size, W.outerIndexPtr(), W.innerIndexPtr(), nullptr, &lu.symbolic, lu.control,
                          lu.info) != UMFPACK_OK)
    return false;
  const double predicted = std::max(lu.info[UMFPACK_FLOPS_ESTIMATE], 0.0);
  // A solve and its refinement step: each a pass over L and U and a product by J (the estimates of L's
  // and U's entries are upper bounds, as the flops').
  const auto solve_cost = [&](double entries) {
    return (1.0 + lu.control[UMFPACK_IRSTEP]) * (4.0 * entries + product_flops) + product_flops;
  };
  const double predicted_solve =
      solve_cost(std::max(lu.info[UMFPACK_LNZ_ESTIMATE], 0.0) + std::max(lu.info[UMFPACK_UNZ_ESTIMATE], 0.0));

  std::vector<ContactJacobian> jacobian(static_cast<std::size_t>(problem.contacts));
  std::vector<double> values;
  Eigen::VectorXd u = W * r + problem.b, F, F_trial, u_trial, trial, step, check;
  budget.spent += product_flops;
  evaluate(problem, rho, r, u, F, &jacobian);
  double merit = F.squaredNorm();
  bool regularize = false;
  int iteration = 0;
  // A factorization of J + δ I and its solve into `step`; false if refused by the budget or failed.
  // Room is kept for the solve, the line search's first trial and the caller's residual check.
  const auto newton_step = [&](double delta) {
    if (!budget.allows(predicted, predicted_solve, 2.0 * product_flops)) return false;
    assemble(W, d, jacobian, delta, values);
    if (lu.numeric) umfpack_di_free_numeric(&lu.numeric);
    const int status = umfpack_di_numeric(W.outerIndexPtr(), W.innerIndexPtr(), values.data(), lu.symbolic,
                                          &lu.numeric, lu.control, lu.info);
    ++budget.factorizations;
    // The symbolic estimate (an upper bound on the fill pivoting may cause), not the flops counted: the
    // numeric factorization's time follows it (10 ms for 1.1e7 estimated, 1.5e6 counted flops on a
    // 463-contact W), its integer work being no flop.
    budget.spent += std::max(predicted, lu.info[UMFPACK_FLOPS]);
    if (status != UMFPACK_OK) return false;  // singular (UMFPACK_WARNING_singular_matrix) or out of memory
    const Eigen::VectorXd rhs = -F;
    step.resize(m);
    if (umfpack_di_solve(UMFPACK_At, W.outerIndexPtr(), W.innerIndexPtr(), values.data(), step.data(), rhs.data(),
                         lu.numeric, lu.control, lu.info) != UMFPACK_OK)
      return false;
    budget.spent += std::min(predicted_solve, solve_cost(lu.info[UMFPACK_LNZ] + lu.info[UMFPACK_UNZ]));
    if (!step.allFinite()) return false;
    multiply(W, values, step, check);
    return (check - rhs).norm() <= 1e-8 * rhs.norm();
  };
  // Backtracking (Armijo on ½‖F‖²); true if a step was taken.
  const auto line_search = [&] {
    double alpha = 1.0;
    for (int halving = 0; halving < 30; ++halving, alpha *= 0.5) {
      if (!budget.allows(2.0 * product_flops)) return false;  // this trial and the caller's check
      trial = r + alpha * step;
      u_trial = W * trial + problem.b;
      budget.spent += product_flops;
      evaluate(problem, rho, trial, u_trial, F_trial, nullptr);
      const double trial_merit = F_trial.squaredNorm();
      if (trial_merit <= (1.0 - 1e-4 * alpha) * merit) {
        r = trial;
        u = u_trial;
        merit = trial_merit;
        return true;
      }
    }
    return false;
  };
  for (; iteration < max_iterations; ++iteration) {
    const double scale = std::max(scale_b, r.norm());
    if (std::sqrt(merit) <= tolerance * scale) break;
    bool moved = false;
    if (!regularize) {
      moved = newton_step(0.0) && line_search();
      if (!moved && budget.exhausted) break;
      regularize = !moved;
    }
    if (!moved) {
      // √(‖F‖ / scale), not ‖F‖ / scale: the header says why (a singular J's near-null directions).
      const double delta =
          std::min(1e-2, std::max(1e-12, std::sqrt(std::sqrt(merit) / std::max(scale, 1e-300))));
      const bool solved = newton_step(delta);
      if (budget.exhausted) break;
      ++budget.regularized_steps;
      if (!solved || !line_search()) break;
    }
    evaluate(problem, rho, r, u, F, &jacobian);
  }
  if (statistics) {
    statistics->iterations = iteration;
    statistics->merit = std::sqrt(merit);
  }
  return true;
}

}  // namespace csim
