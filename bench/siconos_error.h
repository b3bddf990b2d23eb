// Siconos' natural-map error of an impulse vector r (relative to max(‖q‖, ‖r‖, ‖u‖)), computed by
// Siconos' own fc3d_compute_error / fc2d_compute_error: the one yardstick of bench_siconos and
// bench_data_floor (docs/contact-problems.md). Built only where libsiconos-numerics-dev is installed.
#pragma once

#include <FrictionContactProblem.h>
#define restrict __restrict  // fc2d_compute_error.h is C99
#include <fc2d_compute_error.h>
#undef restrict
#include <fc3d_compute_error.h>

#include <Eigen/Dense>
#include <cmath>
#include <vector>

namespace csim::bench {

inline double siconos_error(::FrictionContactProblem& problem, const Eigen::VectorXd& r, double tolerance) {
  const int n = problem.dimension * problem.numberOfContacts;
  std::vector<double> reaction(r.data(), r.data() + n), velocity(n, 0.0);
  double norm_q = 0.0;
  for (int i = 0; i < n; ++i) norm_q += problem.q[i] * problem.q[i];
  norm_q = std::sqrt(norm_q);
  double error = NAN;
  if (problem.dimension == 3)
    fc3d_compute_error(&problem, reaction.data(), velocity.data(), tolerance, nullptr, norm_q, &error);
  else
    fc2d_compute_error(&problem, reaction.data(), velocity.data(), tolerance, norm_q, &error);
  return error;
}

}  // namespace csim::bench
