// The per-contact pieces of projected Gauss–Seidel shared by its dense and sparse paths (dense_sweep.cpp,
// sparse_pgs.cpp): the local solve, the cone, the status of an impulse and one contact's Gauss–Seidel
// update. Internal to contact/.
#pragma once

#include "contact/coulomb_local.h"

#include <Eigen/Dense>
#include <algorithm>
#include <limits>
#include <cmath>

namespace csim::pgs_local {

template <int D>
using Vector = Eigen::Matrix<double, D, 1>;
template <int D>
using Matrix = Eigen::Matrix<double, D, D>;

// An impulse whose elliptic radius is within this relative distance of r_n is reported as slip: the
// local solves put slipping impulses on the boundary to round-off, and a stick solution lying on the
// boundary to the same precision is at the stick/slip threshold, where both descriptions hold.
constexpr double kBoundaryTolerance = 1e-9;

// `start`: the contact's impulse before this solve (a 3D slip is searched from its direction first);
// `stick`: W's stick inverse (coulomb_local.h) when the caller keeps it, 3D only (null: formed here).
template <int D>
ContactStatus solve_local(const Matrix<D>& W, const Vector<D>& q, const Eigen::Vector2d& mu, Vector<D>& r,
                          const Vector<D>& start, const StickInverse* stick = nullptr) {
  if constexpr (D == 2) {
    return solve_local_2d(W, q, mu(0), r);
  } else {
    if (stick != nullptr) return solve_local_3d(W, *stick, q, mu, r, start);
    return solve_local_3d(W, q, mu, r, start);
  }
}

// Elliptic radius of r_t over r_n, on the rough axes only; 1 (on the boundary) for a frictionless
// contact, whose disk is the single point r_t = 0.
template <int D>
double cone_ratio(const Vector<D>& r, const Eigen::Vector2d& mu) {
  double radius_squared = 0.0;
  bool rough = false;
  for (int k = 1; k < D; ++k) {
    if (mu(k - 1) > 0) {
      rough = true;
      radius_squared += (r(k) / mu(k - 1)) * (r(k) / mu(k - 1));
    }
  }
  return rough ? std::sqrt(radius_squared) / r(0) : 1.0;
}

template <int D>
ContactStatus status_of(const Vector<D>& r, const Eigen::Vector2d& mu) {
  if (!(r(0) > 0)) return ContactStatus::open;
  return cone_ratio<D>(r, mu) < 1.0 - kBoundaryTolerance ? ContactStatus::stick : ContactStatus::slip;
}

// Over-relaxation (omega > 1) can carry an impulse out of the cone; pull it back radially (in the
// elliptic metric) so that every iterate stays admissible. Smooth axes are zeroed.
template <int D>
void keep_in_cone(Vector<D>& r, const Eigen::Vector2d& mu) {
  r(0) = std::max(r(0), 0.0);
  for (int k = 1; k < D; ++k)
    if (!(mu(k - 1) > 0)) r(k) = 0.0;
  const double ratio = cone_ratio<D>(r, mu);
  if (ratio > 1.0) r.template tail<D - 1>() *= r(0) > 0 ? 1.0 / ratio : 0.0;
}

// What a sweep learnt on its way, for the convergence tests (pgs_solver.h).
struct SweepResult {
  double increment_squared = 0.0;  // Σ (W_ii Δr_i)², (m/s)²
  double Wr_squared = 0.0;         // ≈ ‖W r‖², from the velocities seen during the sweep, (m/s)²
  // The contacts from this one on have a zero term in the full residual at the sweep's result, known
  // without solving them again: after the last contact whose impulse moved, no impulse changed, so
  // each later contact (and that one, if its impulse is its local solution, omega = 1) sees at the end
  // the frozen velocity it was solved with, and its local solution is its impulse bit for bit. 0 when
  // every local solve returned the impulse it started from; a rejected contact is never settled.
  int settled_from = 0;
};

// One contact's term of the full residual's law part (pgs_solver.h), ‖W_cc (r_c − local_c)‖², local_c
// the contact's local solution at its frozen free velocity `frozen`; infinite when that solution is not
// finite.
template <int D>
double law_term(const Matrix<D>& W_cc, const Vector<D>& frozen, const Eigen::Vector2d& mu, const Vector<D>& r_c,
                const StickInverse* stick = nullptr) {
  Vector<D> r_local;
  solve_local<D>(W_cc, frozen, mu, r_local, r_c, stick);
  if (!r_local.allFinite()) return std::numeric_limits<double>::infinity();
  return (W_cc * (r_c - r_local)).squaredNorm();
}

// One contact's Gauss–Seidel update within a sweep: its local problem (W_cc, the frozen free velocity
// `frozen` = b_c + Σ_{d≠c} W_cd r_d) solved exactly, the impulse r_c (D entries from r_c's start)
// relaxed by omega, and the sweep's sums in `result` updated; `b_c` is the contact's own free term, from which
// (W r)_c = (frozen − b_c) + W_cc r_c. A non-finite local result is rejected (counted, r_c kept).
// `stick`: W_cc's stick inverse, when the caller keeps it (solve_local).
template <int D>
void update_contact(int c, const Matrix<D>& W_cc, const Vector<D>& frozen, const Vector<D>& b_c,
                    const Eigen::Vector2d& mu, double omega, double* r_c, SweepResult& result, int& rejected,
                    const StickInverse* stick = nullptr) {
  Eigen::Map<Vector<D>> r_contact(r_c);
  const Vector<D> r_old = r_contact;
  Vector<D> r_local;
  solve_local<D>(W_cc, frozen, mu, r_local, r_old, stick);
  if (!r_local.allFinite()) {
    ++rejected;
    result.settled_from = c + 1;
    result.Wr_squared += (frozen - b_c + W_cc * r_old).squaredNorm();
    return;
  }
  Vector<D> r_new = r_local;
  if (omega != 1.0) {
    r_new = r_old + omega * (r_local - r_old);
    if (omega > 1.0) keep_in_cone<D>(r_new, mu);
  }
  if (r_new != r_old || r_local != r_new) result.settled_from = r_local == r_new ? c : c + 1;
  result.increment_squared += W_cc.diagonal().cwiseProduct(r_new - r_old).squaredNorm();
  result.Wr_squared += (frozen - b_c + W_cc * r_new).squaredNorm();
  r_contact = r_new;
}

// Denominator of the relative residuals: the velocity scale of the problem.
inline double velocity_scale(double norm_b, double norm_Wr) { return std::max({norm_b, norm_Wr, 1e-300}); }

}  // namespace csim::pgs_local
