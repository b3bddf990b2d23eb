// The contact solver tests' shared problems and checks: the files of tests/contact/data in csim's
// text format and in Siconos', a small unsymmetric problem solved by hand, Siconos' natural-map error
// (which judges a solution independently of the solver's own residual), and the polish budget's check
// that both of PgsSolver's paths pass.
#pragma once

#include "contact/friction_contact_problem.h"
#include "contact/pgs_solver.h"
#include "contact/siconos_problem_format.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>

namespace csim::test {

inline std::ifstream open_data(const std::string& path) {
  std::ifstream file(std::string(CSIM_SOURCE_DIR "/tests/contact/data/") + path);
  if (!file) throw std::runtime_error("cannot open tests/contact/data/" + path);
  return file;
}

// tests/contact/data/<name>, csim's text format (friction_contact_problem.h).
inline FrictionContactProblem problem_file(const std::string& name) {
  std::ifstream file = open_data(name);
  return read_problem(file);
}

// tests/contact/data/siconos/<name>, Siconos' format (siconos_problem_format.h).
inline FrictionContactProblem siconos_file(const std::string& name) {
  std::ifstream file = open_data("siconos/" + name);
  return read_siconos_problem(file);
}

// Two frictional contacts (μ = 0.3), W stored dense and unsymmetric in its normal–normal,
// tangent–tangent and normal–tangent couplings. The solution, chosen first and b = u − W r formed from it:
//   r = (1, 1/10, 1, −3/10), u = (0, 0, 0, 2/5): contact 1 sticks (|r_t| = 0.1 < 0.3), contact 2 slips
//   along +t with its friction −μ r_n against it.
// Enumerating the 4 × 4 status combinations (open, stick, slip ±) in exact rational arithmetic finds
// this one only; the same enumeration on Wᵀ gives both contacts slipping, r = (2551/1660, −7653/16600,
// 13/83, −39/830), which is what reading W's columns converged to.
inline FrictionContactProblem unsymmetric_frictional() {
  FrictionContactProblem problem;
  problem.dimension = 2;
  problem.contacts = 2;
  problem.W.resize(4, 4);
  problem.W << 2.0, 0.5, 1.0, 0.0,  //
      0.0, 1.0, 0.0, 0.5,           //
      0.0, 0.0, 2.0, 0.5,           //
      0.5, 0.0, 0.0, 1.0;
  problem.b.resize(4);
  problem.b << -61.0 / 20, 1.0 / 20, -37.0 / 20, 1.0 / 5;
  problem.mu.assign(2, Eigen::Vector2d(0.3, 0.3));
  return problem;
}

// Siconos' natural-map error of r (fc3d_compute_error, fc2d_compute_error with ρ = 1; De Saxcé's
// modified velocity): Σ_c ‖r_c − P_K(r_c − (u_c + μ‖u_t‖ e_n))‖², its square root relative to
// max(‖b‖, ‖r‖, ‖u‖), K the isotropic Coulomb cone; dimensionless. W stored either way, no equality rows.
inline double natural_map_error(const FrictionContactProblem& problem, const Eigen::VectorXd& r) {
  const Eigen::VectorXd u =
      (problem.storage == DelassusStorage::sparse ? Eigen::VectorXd(problem.W_sparse * r) : Eigen::VectorXd(problem.W * r)) +
      problem.b;
  const int d = problem.dimension;
  double error = 0.0;
  for (int c = 0; c < problem.contacts; ++c) {
    const double mu = problem.mu[c](0);
    const Eigen::VectorXd r_c = r.segment(d * c, d), u_c = u.segment(d * c, d);
    Eigen::VectorXd v = r_c - u_c;
    v(0) -= mu * u_c.tail(d - 1).norm();
    const double normal = v(0), tangent = v.tail(d - 1).norm();
    Eigen::VectorXd projected = v;
    if (mu * tangent <= -normal) {
      projected.setZero();
    } else if (tangent > mu * normal) {
      const double n = (mu * tangent + normal) / (mu * mu + 1.0);
      projected(0) = n;
      projected.tail(d - 1) = mu * n * v.tail(d - 1) / tangent;
    }
    error += (r_c - projected).squaredNorm();
  }
  return std::sqrt(error) / std::max({problem.b.norm(), r.norm(), u.norm()});
}

// A problem that needs the polish (Gauss–Seidel alone stalls: the box on four vertices of a stiff block)
// solved at polish_budget 0, 1 and 10, no allowance: the polish's work stays within polish_budget times
// the sweeps' (flops), with none it does nothing (cut, unconverged), and with 10 it converges.
inline void expect_polish_within_budget(const FrictionContactProblem& problem) {
  for (const double budget : {0.0, 1.0, 10.0}) {
    PgsParameters parameters;
    parameters.tolerance = 1e-12;
    parameters.polish_budget = budget;
    parameters.polish_allowance = 0.0;
    Eigen::VectorXd r;
    const PgsStatistics statistics = PgsSolver(parameters).solve(problem, r);
    EXPECT_LE(statistics.polish_work, budget * statistics.sweep_work) << budget;
    EXPECT_GT(statistics.sweep_work, 0.0);
    if (budget == 0.0) {
      EXPECT_EQ(statistics.polish_factorizations, 0);
      EXPECT_TRUE(statistics.polish_cut);
      EXPECT_FALSE(statistics.converged);
    }
    if (budget == 10.0) {
      EXPECT_TRUE(statistics.converged) << statistics.residual;
    }
  }
}

}  // namespace csim::test
