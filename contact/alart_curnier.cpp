#include "contact/alart_curnier.h"

#include "contact/polish_budget.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace csim {

namespace {

// F(r) and, when J is given, an element of its generalized Jacobian (see the header).
void evaluate(const FrictionContactProblem& problem, const Eigen::VectorXd& rho, const Eigen::VectorXd& r,
              Eigen::VectorXd& F, Eigen::MatrixXd* J) {
  const int d = problem.dimension, t = d - 1;
  const Eigen::Index m = problem.size();
  const Eigen::VectorXd u = problem.W * r + problem.b;
  F.resize(m);
  if (J) J->setZero(m, m);
  for (int c = 0; c < problem.contacts; ++c) {
    const Eigen::Index n = static_cast<Eigen::Index>(d) * c;
    const double p = rho(c), mu = problem.mu[c](0);
    // Normal part.
    const double a_n = r(n) - p * u(n);
    const bool pressed = a_n > 0.0;
    if (pressed) {
      F(n) = p * u(n);
      if (J) J->row(n) = p * problem.W.row(n);
    } else {
      F(n) = r(n);
      if (J) (*J)(n, n) = 1.0;
    }
    // Tangential part: τ = r_t − ρ u_t projected on the disk of radius R = μ max(0, a_n).
    const double R = pressed ? mu * a_n : 0.0;
    Eigen::VectorXd tau(t);
    for (int k = 0; k < t; ++k) tau(k) = r(n + 1 + k) - p * u(n + 1 + k);
    const double norm = tau.norm();
    if (!(R > 0.0)) {  // open or frictionless: r_t = 0
      for (int k = 0; k < t; ++k) {
        F(n + 1 + k) = r(n + 1 + k);
        if (J) (*J)(n + 1 + k, n + 1 + k) = 1.0;
      }
    } else if (norm <= R) {  // stick: u_t = 0
      for (int k = 0; k < t; ++k) {
        F(n + 1 + k) = p * u(n + 1 + k);
        if (J) J->row(n + 1 + k) = p * problem.W.row(n + 1 + k);
      }
    } else {  // slip: r_t = R τ / |τ|
      const Eigen::VectorXd direction = tau / norm;
      for (int k = 0; k < t; ++k) F(n + 1 + k) = r(n + 1 + k) - R * direction(k);
      if (J) {
        // ∂τ_k/∂r = e_{t,k} − ρ W_{t,k}; ∂R/∂r = μ (e_n − ρ W_n); ∂(τ/|τ|) = (I − τ̂τ̂ᵀ) ∂τ / |τ|.
        Eigen::MatrixXd dtau(t, m);
        for (int k = 0; k < t; ++k) {
          dtau.row(k) = -p * problem.W.row(n + 1 + k);
          dtau(k, n + 1 + k) += 1.0;
        }
        Eigen::RowVectorXd dR = -mu * p * problem.W.row(n);
        dR(n) += mu;
        const Eigen::MatrixXd projector =
            Eigen::MatrixXd::Identity(t, t) - direction * direction.transpose();
        const Eigen::MatrixXd ddirection = projector * dtau / norm;
        for (int k = 0; k < t; ++k) {
          J->row(n + 1 + k) = -direction(k) * dR - R * ddirection.row(k);
          (*J)(n + 1 + k, n + 1 + k) += 1.0;
        }
      }
    }
  }
  const Eigen::Index first = static_cast<Eigen::Index>(d) * problem.contacts;
  for (Eigen::Index e = first; e < m; ++e) {
    const double p = rho(problem.contacts + (e - first));
    F(e) = p * u(e);
    if (J) J->row(e) = p * problem.W.row(e);
  }
}

// Flops of a dense LU of size k with its solve and the check of its residual.
double lu_flops(double k) { return 2.0 / 3.0 * k * k * k + 6.0 * k * k; }

enum class StepOutcome { solved, unsolved, refused };

// The Newton step (J + δ I) s = −F into `step`. A sticking contact whose W has an empty tangent row and
// column (the direction of a node held by a support, as a 3D ring's axial direction under plane strain)
// leaves J with the same row and column empty: that component of F (ρ b, which no impulse changes) is
// out of Newton's reach, and no other component depends on that impulse. Its step is 0, and the other
// rows are solved by partial pivoting. `unsolved`: the plain step (δ = 0) does not solve its system to
// 1e-8 (J singular on a hyperstatic contact set); `refused`: the budget has no room for the
// factorization, the solve and `reserve` flops after it.
StepOutcome newton_step(const Eigen::MatrixXd& J, const Eigen::VectorXd& F, double delta, double reserve,
                        PolishBudget& budget, Eigen::VectorXd& step) {
  const Eigen::Index m = J.rows();
  std::vector<Eigen::Index> kept;
  kept.reserve(static_cast<std::size_t>(m));
  for (Eigen::Index i = 0; i < m; ++i)
    if (!(J.row(i).isZero(0.0) && J.col(i).isZero(0.0))) kept.push_back(i);
  const auto k = static_cast<Eigen::Index>(kept.size());
  step.setZero(m);
  if (k == 0) return StepOutcome::solved;
  const double flops = lu_flops(static_cast<double>(k));
  if (!budget.allows(flops + reserve)) return StepOutcome::refused;
  Eigen::MatrixXd reduced(k, k);
  Eigen::VectorXd rhs(k);
  for (Eigen::Index j = 0; j < k; ++j) {
    rhs(j) = -F(kept[j]);
    for (Eigen::Index i = 0; i < k; ++i) reduced(i, j) = J(kept[i], kept[j]);
  }
  reduced.diagonal().array() += delta;
  const Eigen::VectorXd part = reduced.partialPivLu().solve(rhs);
  budget.spent += flops;
  ++budget.factorizations;
  if (delta > 0.0) ++budget.regularized_steps;
  if (!part.allFinite()) return StepOutcome::unsolved;
  for (Eigen::Index j = 0; j < k; ++j) step(kept[j]) = part(j);
  if (delta > 0.0) return StepOutcome::solved;  // an approximation of Newton's by construction
  return (reduced * part - rhs).norm() <= 1e-8 * rhs.norm() ? StepOutcome::solved : StepOutcome::unsolved;
}

}  // namespace

bool alart_curnier_newton(const FrictionContactProblem& problem, Eigen::VectorXd& r, int max_iterations,
                          double tolerance, NewtonStatistics* statistics, double rho_scale, PolishBudget* given_budget) {
  for (int c = 0; c < problem.contacts; ++c)
    if (problem.dimension == 3 && problem.mu[c](0) != problem.mu[c](1)) return false;
  const int d = problem.dimension;
  const Eigen::Index m = problem.size();
  if (m == 0 || r.size() != m) return false;
  // ρ per contact (1 / mean diagonal of W_cc) and per equality row (1 / W_ee).
  Eigen::VectorXd rho(problem.contacts + problem.equalities);
  for (int c = 0; c < problem.contacts; ++c)
    rho(c) = rho_scale * d / std::max(problem.W.diagonal().segment(static_cast<Eigen::Index>(d) * c, d).sum(), 1e-300);
  for (int e = 0; e < problem.equalities; ++e) {
    const Eigen::Index row = static_cast<Eigen::Index>(d) * problem.contacts + e;
    rho(problem.contacts + e) = rho_scale / std::max(problem.W(row, row), 1e-300);
  }
  Eigen::VectorXd rho_b = problem.b;
  for (int c = 0; c < problem.contacts; ++c) rho_b.segment(static_cast<Eigen::Index>(d) * c, d) *= rho(c);
  for (int e = 0; e < problem.equalities; ++e) rho_b(static_cast<Eigen::Index>(d) * problem.contacts + e) *= rho(problem.contacts + e);

  // F alone costs a product by W; F with J about twice that (J's rows are W's, scaled).
  const double size = static_cast<double>(m), merit_flops = 2.0 * size * size, jacobian_flops = 2.0 * merit_flops;
  // Without a budget, one that refuses nothing (and whose counts nobody reads).
  PolishBudget unbounded;
  PolishBudget& budget = given_budget != nullptr ? *given_budget : unbounded;
  if (statistics) *statistics = NewtonStatistics{};
  if (!budget.afford(jacobian_flops)) return true;
  Eigen::VectorXd F, F_trial, step, trial;
  Eigen::MatrixXd J;
  evaluate(problem, rho, r, F, &J);
  double merit = F.squaredNorm();
  bool regularize = false;  // the plain step failed once: J is singular at these statuses, take the proximal one
  int iteration = 0;
  // Room kept after a factorization: the line search's first trial, the next Jacobian, a caller's check.
  const double reserve = 2.0 * merit_flops + jacobian_flops;
  for (; iteration < max_iterations; ++iteration) {
    const double scale = std::max(rho_b.norm(), r.norm());
    if (std::sqrt(merit) <= tolerance * scale) break;
    StepOutcome outcome = StepOutcome::unsolved;
    if (!regularize) outcome = newton_step(J, F, 0.0, reserve, budget, step);
    if (outcome == StepOutcome::refused) break;
    if (outcome == StepOutcome::unsolved) {
      regularize = true;
      const double delta = std::min(1e-2, std::max(1e-12, std::sqrt(merit) / std::max(scale, 1e-300)));
      outcome = newton_step(J, F, delta, reserve, budget, step);
      if (outcome != StepOutcome::solved) break;
    }
    if (!step.allFinite()) break;
    // Backtracking (Armijo on ½‖F‖², with the Newton direction's model decrease ‖F‖²).
    double alpha = 1.0;
    bool accepted = false;
    for (int halving = 0; halving < 30 && budget.allows(merit_flops + jacobian_flops); ++halving, alpha *= 0.5) {
      trial = r + alpha * step;
      evaluate(problem, rho, trial, F_trial, nullptr);
      budget.spent += merit_flops;
      const double trial_merit = F_trial.squaredNorm();
      if (trial_merit <= (1.0 - 1e-4 * alpha) * merit) {
        r = trial;
        merit = trial_merit;
        accepted = true;
        break;
      }
    }
    if (!accepted) break;
    evaluate(problem, rho, r, F, &J);
    budget.spent += jacobian_flops;
  }
  if (statistics) {
    statistics->iterations = iteration;
    statistics->merit = std::sqrt(merit);
  }
  return true;
}

}  // namespace csim
