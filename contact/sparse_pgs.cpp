#include "contact/sparse_pgs.h"

#include "contact/body_block_velocities.h"
#include "contact/pgs_iteration.h"
#include "contact/pgs_local.h"
#include "contact/sparse_active_set.h"
#include "contact/sparse_alart_curnier.h"
#include "contact/whole_blocks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace csim {
namespace {

using pgs_local::Matrix;
using pgs_local::SweepResult;
using pgs_local::Vector;
using pgs_local::update_contact;
using pgs_local::velocity_scale;

constexpr int kNewtonIterations = 30;

// True if W is laid out as the sweeps and the Newton polish read it: compressed rows, sorted columns in
// whole aligned d × d blocks, the d rows of a contact with the same columns, every diagonal block stored.
bool has_block_layout(const SparseDelassus& W, int d) {
  if (!W.isCompressed()) return false;
  const int* outer = W.outerIndexPtr();
  const int* inner = W.innerIndexPtr();
  for (Eigen::Index n = 0; n < W.rows(); n += d) {
    const int start = outer[n], length = outer[n + 1] - start;
    if (length % d != 0) return false;
    for (int k = 1; k < d; ++k) {
      if (outer[n + k + 1] - outer[n + k] != length) return false;
      if (!std::equal(inner + start, inner + start + length, inner + outer[n + k])) return false;
    }
    bool diagonal = false;
    int previous = -1;
    for (int pos = start; pos < start + length; pos += d) {
      const int column = inner[pos];
      if (column % d != 0 || column <= previous) return false;
      for (int k = 1; k < d; ++k)
        if (inner[pos + k] != column + k) return false;
      diagonal = diagonal || column == n;
      previous = column + d - 1;
    }
    if (!diagonal) return false;
  }
  return true;
}

// W's entries with every diagonal block added, completed to whole blocks.
SparseDelassus completed_layout(const SparseDelassus& W, int d) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(W.nonZeros() + W.rows()));
  for (Eigen::Index i = 0; i < W.outerSize(); ++i)
    for (SparseDelassus::InnerIterator it(W, i); it; ++it) entries.emplace_back(it.row(), it.col(), it.value());
  for (Eigen::Index i = 0; i < W.rows(); ++i) entries.emplace_back(i, i, 0.0);
  SparseDelassus result = whole_blocks(static_cast<int>(W.rows()), d, entries);
  result.makeCompressed();
  return result;
}

// W read by contact rows, copied once per solve into block rows: each contact's diagonal block, and its
// other D × D blocks with their contacts, contiguous. A frozen velocity is then a few small dense
// products, one column index a block, where the compressed rows load one index an entry (1000 dropped
// spheres: about a third fewer instructions a sweep).
// With W's body-block factors (friction_contact_problem.h) only the diagonal blocks are copied: W r is
// then applied through the bodies (body_block_velocities.h), never by W's rows.
template <int D>
struct BlockRows {
  const SparseDelassus& W;
  const BodyBlockDelassus* factors = nullptr;
  std::vector<Matrix<D>> diagonal;
  std::vector<int> first_block;  // contact c's blocks: [first_block[c], first_block[c + 1])
  std::vector<int> block_contact;
  std::vector<Matrix<D>> block;
  // The residual's W r through the factors (its own, so that it never disturbs the sweeps' velocities).
  mutable std::optional<BodyBlockVelocities<D>> residual_velocities;
  // 3D: each diagonal block's stick inverse (coulomb_local.h), formed once per solve for every sweep's
  // local solves.
  std::vector<StickInverse> stick;
  const StickInverse* stick_of(int c) const {
    if constexpr (D == 3) return &stick[c];
    else return nullptr;
  }

  BlockRows(const SparseDelassus& W_in, const BodyBlockDelassus* factors_in) : W(W_in), factors(factors_in) {
    const int* outer = W.outerIndexPtr();
    const int* inner = W.innerIndexPtr();
    const double* value = W.valuePtr();
    const int contacts = static_cast<int>(W.rows()) / D;
    diagonal.resize(static_cast<std::size_t>(contacts));
    first_block.resize(static_cast<std::size_t>(contacts) + 1);
    const std::size_t blocks = factors != nullptr ? 0 : static_cast<std::size_t>(W.nonZeros()) / (D * D);
    block_contact.reserve(blocks);
    block.reserve(blocks);
    if (factors != nullptr) residual_velocities.emplace(*factors);
    for (int c = 0; c < contacts; ++c) {
      const int n = D * c;
      first_block[c] = static_cast<int>(block.size());
      for (int pos = outer[n]; pos < outer[n + 1]; pos += D) {
        if (factors != nullptr && inner[pos] != n) continue;
        const int offset = pos - outer[n];
        Matrix<D> entries;
        for (int i = 0; i < D; ++i)
          for (int j = 0; j < D; ++j) entries(i, j) = value[outer[n + i] + offset + j];
        if (inner[pos] == n) {
          diagonal[c] = entries;
        } else {
          block_contact.push_back(inner[pos] / D);
          block.push_back(entries);
        }
      }
    }
    first_block[contacts] = static_cast<int>(block.size());
    if constexpr (D == 3) {
      stick.resize(static_cast<std::size_t>(contacts));
      for (int c = 0; c < contacts; ++c) stick[c] = stick_inverse(diagonal[c]);
    }
  }
};

// b_c + Σ_{d≠c} W_cd r_d (m/s), the own block skipped (so that a single contact sees b_c exactly).
template <int D>
Vector<D> frozen_free_velocity(const FrictionContactProblem& problem, const BlockRows<D>& W, const Eigen::VectorXd& r,
                               int c) {
  Vector<D> b_c = problem.b.template segment<D>(D * c);
  const double* x = r.data();
  for (int k = W.first_block[c]; k < W.first_block[c + 1]; ++k)
    b_c.noalias() += W.block[k] * Eigen::Map<const Vector<D>>(x + D * W.block_contact[k]);
  return b_c;
}

template <int D>
double product_squared(const FrictionContactProblem& problem, int c, const Vector<D>& frozen, const Matrix<D>& W_cc,
                       const Vector<D>& r_c) {
  return (frozen - problem.b.template segment<D>(D * c) + W_cc * r_c).squaredNorm();
}

template <int D>
SweepResult sweep(const FrictionContactProblem& problem, const BlockRows<D>& W, double omega, Eigen::VectorXd& r,
                  int& rejected) {
  SweepResult result;
  for (int c = 0; c < problem.contacts; ++c) {
    const int first = D * c;
    update_contact<D>(c, W.diagonal[c], frozen_free_velocity<D>(problem, W, r, c), problem.b.template segment<D>(first),
                      problem.mu[c], omega, r.data() + first, result, rejected, W.stick_of(c));
  }
  return result;
}

// The same sweep with W applied through its body-block factors: `velocities` holds w of r on entry and
// on exit; a contact's frozen velocity is b_c + (W r)_c − W_cc r_c, and its change of impulse is added to
// its bodies' w at once (Gauss–Seidel: the next contact sees it).
template <int D>
SweepResult sweep_by_bodies(const FrictionContactProblem& problem, const BlockRows<D>& W, double omega,
                            Eigen::VectorXd& r, int& rejected, BodyBlockVelocities<D>& velocities) {
  SweepResult result;
  for (int c = 0; c < problem.contacts; ++c) {
    const int first = D * c;
    const Vector<D> r_old = r.template segment<D>(first);
    const Vector<D> b_c = problem.b.template segment<D>(first);
    const Vector<D> frozen = b_c + velocities.velocity(c) - W.diagonal[c] * r_old;
    update_contact<D>(c, W.diagonal[c], frozen, b_c, problem.mu[c], omega, r.data() + first, result, rejected,
                      W.stick_of(c));
    const Vector<D> change = r.template segment<D>(first) - r_old;
    if (change != Vector<D>::Zero()) velocities.add(c, change);
  }
  return result;
}

// The full relative residual (pgs_solver.h) with W applied through its body-block factors.
template <int D>
double relative_residual_by_bodies(const FrictionContactProblem& problem, const BlockRows<D>& W,
                                   const Eigen::VectorXd& r, int settled_from) {
  BodyBlockVelocities<D>& velocities = *W.residual_velocities;
  velocities.assign(r);
  double law = 0.0, product = 0.0;
  for (int c = 0; c < problem.contacts; ++c) {
    const Vector<D> Wr_c = velocities.velocity(c);
    const Matrix<D>& W_cc = W.diagonal[c];
    const Vector<D> r_c = r.template segment<D>(D * c);
    product += Wr_c.squaredNorm();
    if (c >= settled_from) continue;
    const Vector<D> frozen = problem.b.template segment<D>(D * c) + Wr_c - W_cc * r_c;
    const double term = pgs_local::law_term<D>(W_cc, frozen, problem.mu[c], r_c, W.stick_of(c));
    if (std::isinf(term)) return term;
    law += term;
  }
  const double residual = std::sqrt(law) / velocity_scale(problem.b.norm(), std::sqrt(product));
  return std::isnan(residual) ? std::numeric_limits<double>::infinity() : residual;
}

// The full relative residual (pgs_solver.h); the contacts from settled_from on are known to add zero.
template <int D>
double relative_residual(const FrictionContactProblem& problem, const BlockRows<D>& W, const Eigen::VectorXd& r,
                         int settled_from) {
  if (W.factors != nullptr) return relative_residual_by_bodies<D>(problem, W, r, settled_from);
  double law = 0.0, product = 0.0;
  for (int c = 0; c < problem.contacts; ++c) {
    const Vector<D> b_c = frozen_free_velocity<D>(problem, W, r, c);
    const Matrix<D>& W_cc = W.diagonal[c];
    const Vector<D> r_c = r.template segment<D>(D * c);
    product += product_squared<D>(problem, c, b_c, W_cc, r_c);
    if (c >= settled_from) continue;
    const double term = pgs_local::law_term<D>(W_cc, b_c, problem.mu[c], r_c, W.stick_of(c));
    if (std::isinf(term)) return term;
    law += term;
  }
  const double residual = std::sqrt(law) / velocity_scale(problem.b.norm(), std::sqrt(product));
  return std::isnan(residual) ? std::numeric_limits<double>::infinity() : residual;
}

// Passes of the active-set iteration per start (each: one sparse factorization, sparse_active_set.h).
constexpr int kActiveSetPasses = 8;

// The active-set iteration from the statuses of r (all closed contacts in stick if closed_stick), each
// pass's solution kept in r when its full residual is smaller. True if r was replaced.
template <int D>
bool active_set_polish(const FrictionContactProblem& problem, const BlockRows<D>& W, Eigen::VectorXd& r,
                       double& residual, double tolerance, bool closed_stick, PolishBudget& budget) {
  const double residual_flops = 2.0 * static_cast<double>(W.W.nonZeros());
  std::vector<ActiveSetStatus> statuses = statuses_of(problem, r, closed_stick);
  Eigen::VectorXd start = r, candidate;
  bool improved = false;
  double previous = std::numeric_limits<double>::infinity();  // the last pass's candidate's residual
  for (int pass = 0; pass < kActiveSetPasses && residual > tolerance; ++pass) {
    if (!solve_active_set(problem, W.W, statuses, start, candidate, budget)) break;
    // The residual, and the velocities of the statuses' correction.
    if (!budget.afford(2.0 * residual_flops)) break;
    const double candidate_residual = relative_residual<D>(problem, W, candidate, problem.contacts);
    if (candidate_residual < residual) {
      r = candidate;
      residual = candidate_residual;
      improved = true;
    }
    // Statuses that do not bring the candidates closer to the law are wandering (each pass a new
    // wrong guess: 7, 13, then 225 on OneObject-i100000-316 of Siconos' tests): the iteration stops
    // there, where on a stack it converges (BoxesStack1: 0.1, 0.014, 0.0026, 1e-7, 8e-15).
    if (!(candidate_residual < previous)) break;
    previous = candidate_residual;
    if (!correct_statuses(problem, W.W, candidate, statuses)) break;
    start = candidate;
  }
  return improved;
}

// Newton from `start` at ρ scales 1 and 1e3, within the budget; a result replaces r only if its full
// residual is smaller. True if r was replaced.
template <int D>
bool newton_polish(const FrictionContactProblem& problem, const BlockRows<D>& W, const Eigen::VectorXd& start,
                   Eigen::VectorXd& r, double& residual, double tolerance, PolishBudget& budget) {
  const double residual_flops = 2.0 * static_cast<double>(W.W.nonZeros());
  bool improved = false;
  for (const double rho_scale : {1.0, 1e3}) {
    if (residual <= tolerance || budget.exhausted) break;
    Eigen::VectorXd candidate = start;
    NewtonStatistics newton;
    if (!sparse_alart_curnier_newton(problem, W.W, candidate, kNewtonIterations, 1e-3 * tolerance, rho_scale, budget,
                                     &newton))
      break;
    if (newton.iterations == 0) continue;  // no step taken: the candidate is the start
    const double candidate_residual = relative_residual<D>(problem, W, candidate, problem.contacts);
    budget.spent += residual_flops;
    if (candidate_residual < residual) {
      r = candidate;
      residual = candidate_residual;
      improved = true;
    }
  }
  return improved;
}

// The polish: Newton from the Gauss–Seidel iterate; if it does not reach the tolerance, the active-set
// iteration from the iterate's statuses, then from "every closed contact in stick", and Newton from the
// active set's result. Each result is kept only when its full residual is smaller; all within the
// budget. Newton comes first because the active set, whose statuses wander on granular flows, could
// spend the budget Newton needs there (Siconos' 7002-contact granular flow: solved at 600 sweeps with
// Newton first, 1e-4 with the active set first); on a stack of boxes Newton's failure leaves the
// active set room enough (BoxesStack1).
template <int D>
bool polish(const FrictionContactProblem& problem, const BlockRows<D>& W, Eigen::VectorXd& r, double& residual,
            double tolerance, PolishBudget& budget) {
  const Eigen::VectorXd iterate = r;
  bool improved = newton_polish<D>(problem, W, iterate, r, residual, tolerance, budget);
  if (residual <= tolerance || budget.exhausted) return improved;
  Eigen::VectorXd active_set_result = iterate;
  double active_set_residual = residual;
  bool moved = active_set_polish<D>(problem, W, active_set_result, active_set_residual, tolerance, false, budget);
  if (active_set_residual > tolerance && !budget.exhausted)
    moved = active_set_polish<D>(problem, W, active_set_result, active_set_residual, tolerance, true, budget) || moved;
  if (!moved) return improved;
  r = active_set_result;
  residual = active_set_residual;
  newton_polish<D>(problem, W, active_set_result, r, residual, tolerance, budget);
  return true;
}

// Gauss–Seidel's contraction per sweep below which a scheduled polish is skipped: the sweeps are then
// converging at a steady rate, at least a decade per 230 sweeps, and finish a problem for less than the
// polish would spend (FrictionContactProblem00727 of Siconos' tests: 696 sweeps alone, 29 ms; 400 sweeps
// and three polishes, 260 ms). A stalled iteration (a hyperstatic stack, an ill-conditioned W) contracts
// by 0.999 or more and is polished on schedule; so is any solve that ends unconverged.
constexpr double kStalled = 0.99;

// The sparse path's pieces for the iteration (pgs_iteration.h): sweeps and residuals on W's block rows
// (or through its body-block factors, `velocities` then holding w of the iterate), the polish above,
// skipped on schedule while the sweeps converge at a steady rate.
template <int D>
struct SparsePath {
  const FrictionContactProblem& problem;
  const BlockRows<D>& W;
  const PgsParameters& parameters;
  pgs_local::ContractionWindow window{};
  bool attempt = false;  // the relaxed attempt (solve_relaxed_first), given up once a window stalls
  int sweeps = 0;
  std::optional<BodyBlockVelocities<D>> velocities{};

  // The products by W counted as W's stored entries, whichever way W is applied: the polish's budget
  // (pgs_solver.h) stays a multiple of the same measure.
  double sweep_flops() const { return 2.0 * static_cast<double>(W.W.nonZeros()); }
  SweepResult sweep(Eigen::VectorXd& r, int& rejected) {
    if (velocities) return sweep_by_bodies<D>(problem, W, parameters.omega, r, rejected, *velocities);
    return csim::sweep<D>(problem, W, parameters.omega, r, rejected);
  }
  double residual(const Eigen::VectorXd& r, int settled_from) const {
    return relative_residual<D>(problem, W, r, settled_from);
  }
  bool polish(Eigen::VectorXd& r, double& residual, PolishBudget& budget) {
    const bool replaced = csim::polish<D>(problem, W, r, residual, parameters.tolerance, budget);
    if (replaced && velocities) velocities->assign(r);
    return replaced;
  }
  void observe(const SweepResult& swept, double scale) {
    window.add(swept.increment_squared, scale);
    ++sweeps;
  }
  bool gives_up() const {
    return attempt && sweeps % (pgs_local::ContractionWindow::kWindow + 1) == 0 && stalled();
  }
  bool stalled() const { return !(window.contraction() < kStalled); }
  bool retries_skipped_polish() const { return false; }
  bool at_floor() const { return false; }
  bool ends_with_polish() const { return true; }
};

template <int D>
PgsStatistics solve_dimension(const FrictionContactProblem& problem, const BlockRows<D>& W,
                              const PgsParameters& parameters, Eigen::VectorXd& r, std::vector<ContactStatus>* status,
                              bool attempt = false) {
  SparsePath<D> path{problem, W, parameters};
  path.attempt = attempt;
  if (W.factors != nullptr) {
    path.velocities.emplace(*W.factors);
    path.velocities->assign(r);
  }
  return pgs_local::iterate<D>(problem, parameters, path, r, status);
}

// The relaxed attempt (sparse_pgs.h): its relaxation and its sweeps at most.
constexpr double kRelaxation = 1.5;
constexpr int kRelaxedSweeps = 200;

// A relaxed attempt from the warm start, then, if it did not converge, the solve by `parameters` from
// the same warm start; the counts of both, the better unconverged result.
template <int D>
PgsStatistics solve_relaxed_first(const FrictionContactProblem& problem, const BlockRows<D>& W,
                                  const PgsParameters& parameters, Eigen::VectorXd& r, std::vector<ContactStatus>* status) {
  PgsParameters relaxed = parameters;
  relaxed.omega = kRelaxation;
  relaxed.max_iterations = std::min(parameters.max_iterations, kRelaxedSweeps);
  relaxed.polish = false;
  const Eigen::VectorXd start = r;
  const PgsStatistics attempt = solve_dimension<D>(problem, W, relaxed, r, status, true);
  if (attempt.converged) return attempt;
  const Eigen::VectorXd attempt_r = r;
  const std::vector<ContactStatus> attempt_status = status != nullptr ? *status : std::vector<ContactStatus>{};
  r = start;
  // The polish's budget is the solve's (pgs_solver.h): what the attempt left of it carries over.
  PgsParameters plain = parameters;
  plain.polish_allowance =
      std::max(0.0, parameters.polish_allowance + parameters.polish_budget * attempt.sweep_work - attempt.polish_work);
  PgsStatistics total = solve_dimension<D>(problem, W, plain, r, status);
  if (!total.converged && attempt.residual < total.residual) {
    r = attempt_r;
    if (status != nullptr) *status = attempt_status;
    total.residual = attempt.residual;
  }
  total.iterations += attempt.iterations;
  total.add_work(attempt);
  return total;
}

template <int D>
PgsStatistics solve_sparse_dimension(const FrictionContactProblem& problem, const BlockRows<D>& W,
                                     const PgsParameters& parameters, Eigen::VectorXd& r,
                                     std::vector<ContactStatus>* status) {
  if (parameters.relax_sparse && parameters.omega == 1.0)
    return solve_relaxed_first<D>(problem, W, parameters, r, status);
  return solve_dimension<D>(problem, W, parameters, r, status);
}

// W_sparse itself when its layout is the one read here, else a completed copy in `completed`.
const SparseDelassus& laid_out(const FrictionContactProblem& problem, SparseDelassus& completed) {
  if (problem.equalities > 0)
    throw std::invalid_argument(
        "PgsSolver: a sparse W with equality rows is not solved (their condensation is dense); store W dense "
        "(storage dense) for a problem with equalities");
  if (has_block_layout(problem.W_sparse, problem.dimension)) return problem.W_sparse;
  completed = completed_layout(problem.W_sparse, problem.dimension);
  return completed;
}

}  // namespace

PgsStatistics solve_sparse(const FrictionContactProblem& problem, const PgsParameters& parameters, Eigen::VectorXd& r,
                           std::vector<ContactStatus>* status, SparseDelassus& completed) {
  const SparseDelassus& W = laid_out(problem, completed);
  if (problem.contacts == 0) return pgs_local::without_contacts(status);
  const BodyBlockDelassus* factors = problem.body_blocks.empty() ? nullptr : &problem.body_blocks;
  if (problem.dimension == 2)
    return solve_sparse_dimension<2>(problem, BlockRows<2>(W, factors), parameters, r, status);
  return solve_sparse_dimension<3>(problem, BlockRows<3>(W, factors), parameters, r, status);
}

double sparse_residual(const FrictionContactProblem& problem, const Eigen::VectorXd& r) {
  SparseDelassus completed;
  const SparseDelassus& W = laid_out(problem, completed);
  if (problem.contacts == 0) return 0.0;
  if (problem.dimension == 2) return relative_residual<2>(problem, BlockRows<2>(W, nullptr), r, problem.contacts);
  return relative_residual<3>(problem, BlockRows<3>(W, nullptr), r, problem.contacts);
}

SparseDelassus block_sparse(const Eigen::MatrixXd& W, int dimension) {
  const Eigen::Index m = W.rows();
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index j = 0; j < m; ++j)
    for (Eigen::Index i = 0; i < m; ++i)
      if (W(i, j) != 0.0 || i == j) entries.emplace_back(static_cast<int>(i), static_cast<int>(j), W(i, j));
  SparseDelassus result = whole_blocks(static_cast<int>(m), dimension, entries);
  result.makeCompressed();
  return result;
}

}  // namespace csim
