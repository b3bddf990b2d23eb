#include "contact/sparse_active_set.h"

#include "contact/pgs_local.h"

#include <umfpack.h>

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>

namespace csim {
namespace {

using pgs_local::cone_ratio;
using pgs_local::status_of;

// Proximal parameter of the scaled system (its stick diagonal about one), and the steps at most.
constexpr double kProximal = 1e-8;
constexpr int kProximalSteps = 12;
// A correction larger than this many times the iterate's and the free term's scaled norms is taken as
// the sign of an inconsistent system (its rows dependent with free terms that disagree), not a solution.
constexpr double kLargestCorrection = 1e3;

using ColumnMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// UMFPACK's symbolic and numeric objects, freed on every exit.
struct Umfpack {
  void* symbolic = nullptr;
  void* numeric = nullptr;
  double control[UMFPACK_CONTROL];
  double info[UMFPACK_INFO];
  Umfpack() { umfpack_di_defaults(control); }
  ~Umfpack() {
    if (numeric) umfpack_di_free_numeric(&numeric);
    if (symbolic) umfpack_di_free_symbolic(&symbolic);
  }
  Umfpack(const Umfpack&) = delete;
  Umfpack& operator=(const Umfpack&) = delete;
};

template <int D>
Eigen::Matrix<double, D, 1> segment(const Eigen::VectorXd& r, int c) {
  return r.template segment<D>(static_cast<Eigen::Index>(D) * c);
}

double cone_ratio_of(const Eigen::VectorXd& r, int d, int c, const Eigen::Vector2d& mu) {
  return d == 2 ? cone_ratio<2>(segment<2>(r, c), mu) : cone_ratio<3>(segment<3>(r, c), mu);
}

// The unknowns of a set of statuses: for each row of W, which unknown its impulse is (−1: none, held at
// zero) and with which weight; unknown j's equation is row equation[j] of u; scale[j] its s_c.
struct Unknowns {
  std::vector<int> of_row;
  std::vector<double> weight;
  std::vector<int> equation;
  std::vector<double> scale;
};

Unknowns unknowns_of(const FrictionContactProblem& problem, const SparseDelassus& W,
                     const std::vector<ActiveSetStatus>& statuses) {
  const int d = problem.dimension;
  Unknowns result;
  result.of_row.assign(static_cast<std::size_t>(problem.size()), -1);
  result.weight.assign(static_cast<std::size_t>(problem.size()), 0.0);
  for (int c = 0; c < problem.contacts; ++c) {
    const ActiveSetStatus& s = statuses[static_cast<std::size_t>(c)];
    if (s.status == ContactStatus::open) continue;
    const int n = d * c;
    double trace = 0.0;
    for (int k = 0; k < d; ++k) trace += W.coeff(n + k, n + k);
    const double scale = 1.0 / std::sqrt(std::max(trace / d, 1e-300));
    const int unknown = static_cast<int>(result.equation.size());
    result.equation.push_back(n);
    result.scale.push_back(scale);
    result.of_row[n] = unknown;
    result.weight[n] = 1.0;
    for (int k = 1; k < d; ++k) {
      if (s.status == ContactStatus::slip) {
        result.of_row[n + k] = unknown;
        result.weight[n + k] = s.slip_ratio(k);
      } else if (problem.mu[c](k - 1) > 0.0) {
        result.of_row[n + k] = static_cast<int>(result.equation.size());
        result.weight[n + k] = 1.0;
        result.equation.push_back(n + k);
        result.scale.push_back(scale);
      }
    }
  }
  return result;
}

// Â = S A S (see the header), column-major for UMFPACK.
ColumnMatrix scaled_system(const SparseDelassus& W, const Unknowns& x) {
  const int k = static_cast<int>(x.equation.size());
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < k; ++i) {
    const int row = x.equation[static_cast<std::size_t>(i)];
    for (SparseDelassus::InnerIterator it(W, row); it; ++it) {
      const int j = x.of_row[static_cast<std::size_t>(it.col())];
      if (j < 0) continue;
      entries.emplace_back(i, j, x.scale[i] * it.value() * x.weight[static_cast<std::size_t>(it.col())] * x.scale[j]);
    }
  }
  ColumnMatrix A(k, k);
  A.setFromTriplets(entries.begin(), entries.end());
  A.makeCompressed();
  return A;
}

}  // namespace

std::vector<ActiveSetStatus> statuses_of(const FrictionContactProblem& problem, const Eigen::VectorXd& r,
                                         bool closed_stick) {
  const int d = problem.dimension;
  std::vector<ActiveSetStatus> statuses(static_cast<std::size_t>(problem.contacts));
  for (int c = 0; c < problem.contacts; ++c) {
    ActiveSetStatus& s = statuses[static_cast<std::size_t>(c)];
    s.status = d == 2 ? status_of<2>(segment<2>(r, c), problem.mu[c]) : status_of<3>(segment<3>(r, c), problem.mu[c]);
    if (s.status == ContactStatus::slip) {
      for (int k = 0; k < d; ++k) s.slip_ratio(k) = r(d * c + k) / r(d * c);
    }
    if (closed_stick && s.status != ContactStatus::open) s.status = ContactStatus::stick;
  }
  return statuses;
}

bool solve_active_set(const FrictionContactProblem& problem, const SparseDelassus& W,
                      const std::vector<ActiveSetStatus>& statuses, const Eigen::VectorXd& r,
                      Eigen::VectorXd& candidate, PolishBudget& budget) {
  const Unknowns x = unknowns_of(problem, W, statuses);
  const int k = static_cast<int>(x.equation.size());
  if (k == 0) return false;
  const ColumnMatrix A = scaled_system(W, x);
  ColumnMatrix shifted = A;
  for (int i = 0; i < k; ++i) shifted.coeffRef(i, i) += kProximal;
  shifted.makeCompressed();
  const double product_flops = 2.0 * static_cast<double>(A.nonZeros());

  // ẑ_0 from the iterate (a slip contact's unknown is its r_n), f̂ = −S b on the equations' rows.
  Eigen::VectorXd z(k), f(k);
  for (int j = 0; j < k; ++j) {
    z(j) = r(x.equation[j]) / x.scale[j];
    f(j) = -x.scale[j] * problem.b(x.equation[j]);
  }

  Umfpack lu;
  if (!budget.afford(product_flops)) return false;  // the symbolic analysis, about linear in the entries
  if (umfpack_di_symbolic(k, k, shifted.outerIndexPtr(), shifted.innerIndexPtr(), shifted.valuePtr(), &lu.symbolic,
                          lu.control, lu.info) != UMFPACK_OK)
    return false;
  const double predicted = std::max(lu.info[UMFPACK_FLOPS_ESTIMATE], 0.0);
  const double solve_flops =
      (1.0 + lu.control[UMFPACK_IRSTEP]) *
          (4.0 * (std::max(lu.info[UMFPACK_LNZ_ESTIMATE], 0.0) + std::max(lu.info[UMFPACK_UNZ_ESTIMATE], 0.0)) +
           product_flops) +
      product_flops;
  if (!budget.allows(predicted, solve_flops)) return false;
  const int status = umfpack_di_numeric(shifted.outerIndexPtr(), shifted.innerIndexPtr(), shifted.valuePtr(),
                                        lu.symbolic, &lu.numeric, lu.control, lu.info);
  ++budget.factorizations;
  budget.spent += std::max(predicted, lu.info[UMFPACK_FLOPS]);
  if (status != UMFPACK_OK) return false;

  const double target = 1e-14 * f.norm();
  const double largest = kLargestCorrection * std::max(z.norm(), f.norm());
  Eigen::VectorXd g = A * z - f, step(k), rhs(k);
  for (int iteration = 0; iteration < kProximalSteps && g.norm() > target; ++iteration) {
    if (!budget.afford(solve_flops)) break;
    rhs = -g;
    const int solved = umfpack_di_solve(UMFPACK_A, shifted.outerIndexPtr(), shifted.innerIndexPtr(),
                                        shifted.valuePtr(), step.data(), rhs.data(), lu.numeric, lu.control, lu.info);
    if (solved != UMFPACK_OK || !step.allFinite() || step.norm() > largest) break;
    const Eigen::VectorXd z_next = z + step;
    const Eigen::VectorXd g_next = A * z_next - f;
    if (!(g_next.norm() < g.norm())) break;
    z = z_next;
    g = g_next;
  }

  candidate.setZero(problem.size());
  for (Eigen::Index row = 0; row < problem.size(); ++row) {
    const int j = x.of_row[static_cast<std::size_t>(row)];
    if (j >= 0) candidate(row) = x.weight[static_cast<std::size_t>(row)] * z(j) * x.scale[j];
  }
  return candidate.allFinite();
}

bool correct_statuses(const FrictionContactProblem& problem, const SparseDelassus& W, const Eigen::VectorXd& r,
                      std::vector<ActiveSetStatus>& statuses) {
  const int d = problem.dimension;
  const Eigen::VectorXd u = W * r + problem.b;
  bool changed = false;
  for (int c = 0; c < problem.contacts; ++c) {
    const int n = d * c;
    ActiveSetStatus& s = statuses[static_cast<std::size_t>(c)];
    const ActiveSetStatus before = s;
    if (s.status == ContactStatus::open) {
      if (u(n) < 0.0) s.status = ContactStatus::stick;
    } else if (!(r(n) > 0.0)) {
      s.status = ContactStatus::open;
    } else if (s.status == ContactStatus::stick) {
      const double ratio = cone_ratio_of(r, d, c, problem.mu[c]);
      if (ratio > 1.0) {
        s.status = ContactStatus::slip;
        s.slip_ratio = Eigen::Vector3d::Zero();
        for (int k = 0; k < d; ++k) s.slip_ratio(k) = r(n + k) / (r(n) * ratio);
        s.slip_ratio(0) = 1.0;
      }
    } else {
      double power = 0.0;  // r_t · u_t: positive when the velocity does not oppose the impulse
      for (int k = 1; k < d; ++k) power += r(n + k) * u(n + k);
      if (power > 0.0) s.status = ContactStatus::stick;
    }
    changed = changed || s.status != before.status || s.slip_ratio != before.slip_ratio;
  }
  return changed;
}

}  // namespace csim
