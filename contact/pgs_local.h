// The per-contact pieces of projected Gauss–Seidel shared by its dense and sparse paths (pgs_solver.cpp,
// sparse_pgs.cpp): the local solve, the cone and the status of an impulse. Internal to contact/.
#pragma once

#include "contact/coulomb_local.h"

#include <Eigen/Dense>
#include <algorithm>
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

template <int D>
ContactStatus solve_local(const Matrix<D>& W, const Vector<D>& q, const Eigen::Vector2d& mu, Vector<D>& r) {
  if constexpr (D == 2) {
    return solve_local_2d(W, q, mu(0), r);
  } else {
    return solve_local_3d(W, q, mu, r);
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

// Denominator of the relative residuals: the velocity scale of the problem.
inline double velocity_scale(double norm_b, double norm_Wr) { return std::max({norm_b, norm_Wr, 1e-300}); }

}  // namespace csim::pgs_local
