// Exact solution of the one-contact Coulomb problem u = W r + q (see friction_contact_problem.h for the
// law and sign conventions). These are the local solves of projected Gauss–Seidel: with the other
// contacts frozen, each contact's problem is solved exactly, not by a projection step.
//
// Method (enumeration of the three cases of the law, each solved in closed form or by a 1-D root):
//   open  : r = 0 when q_n ≥ 0;
//   stick : r = −W⁻¹q when r_n > 0 and r_t lies in the (elliptic) disk D(r_n);
//   slip  : u_n = 0 and r_t = r_n·M s on the boundary of D, M = diag(μ1, μ2), |s| = 1, with s
//           opposite to M u_t (maximal dissipation). In 2D, s = ±1 in closed form; in 3D, s = (cos φ,
//           sin φ) is found as the root in φ of s × (M u_t(φ)) = 0 with s·(M u_t) < 0 (Newton from the
//           decoupled guess, safeguarded by bisection once two iterates bracket a root; a scan of the
//           circle as fallback). When W_nt = 0 and W_tt ∝ I (point masses)
//           the first guess is exact.
// μ = 0 (or μ_i = 0) reduces to the frictionless (or unidirectional) law exactly.
#pragma once

#include <Eigen/Dense>

namespace csim {

enum class ContactStatus { open, stick, slip };

const char* to_string(ContactStatus status);

// W(0,0) > 0; W need not be symmetric (the law is read row by row, u = W r + q: a projected Gauss–Seidel
// on an unsymmetric W passes its diagonal block as stored). On return r holds the solution; the status
// says which case.
// Edge cases (clarifications of the contract above):
//   - W_nn ≤ 0, or negligible (≤ 1e-14 × the largest diagonal entry): open, r = 0 (the normal row
//     cannot move, so no impulse can separate it);
//   - any NaN/inf in W or q (or NaN in μ): r is NaN, for the caller to reject;
//   - μ ≤ 0 on every axis: frictionless, r_t = 0; a closed frictionless contact is reported as slip
//     (r_t = 0 is the boundary of the degenerate disk);
//   - μ_i ≤ 0 on one axis of a 3D contact: r_ti = 0 exactly and the other axis follows the 2D law;
//   - when round-off defeats every exact test (at the stick/slip threshold), or no solution exists
//     (singular W, Painlevé-like coupling), the candidate closest to the law is returned.
// The 3D slip root is searched by Newton from the decoupled guess, then from the direction of the
// rejected stick impulse, then by a scan of the circle with safeguarded Newton/bisection in each bracket.
ContactStatus solve_local_2d(const Eigen::Matrix2d& W, const Eigen::Vector2d& q, double mu,
                             Eigen::Vector2d& r);
ContactStatus solve_local_3d(const Eigen::Matrix3d& W, const Eigen::Vector3d& q,
                             const Eigen::Vector2d& mu, Eigen::Vector3d& r);
// The same, with `start` an impulse believed near the solution (N·s, the contact's impulse before this
// solve, as a Gauss–Seidel sweep has it): when start slips (r_n > 0, r_t ≠ 0) the slip root is searched
// by Newton from its direction first, then as above. Where the law has one solution the result is
// the same up to round-off; where it has several, the root nearest the start is favoured.
ContactStatus solve_local_3d(const Eigen::Matrix3d& W, const Eigen::Vector3d& q,
                             const Eigen::Vector2d& mu, Eigen::Vector3d& r, const Eigen::Vector3d& start);

// The stick case's inverse of a 3D W (W r = −q), with the test that says whether it is computable
// (det above 1e-14 of Hadamard's bound W_nn W_t1t1 W_t2t2), as solve_local_3d forms it. Projected
// Gauss–Seidel solves each contact's local problem with the same W_cc at every sweep, and forms it once
// per solve instead (pgs_local.h): the same bits, a third of a stick solve's instructions.
struct StickInverse {
  Eigen::Matrix3d inverse = Eigen::Matrix3d::Zero();
  bool computable = false;
};
StickInverse stick_inverse(const Eigen::Matrix3d& W);
// solve_local_3d from `start`, with `stick` = stick_inverse(W): the same result to the bit.
ContactStatus solve_local_3d(const Eigen::Matrix3d& W, const StickInverse& stick, const Eigen::Vector3d& q,
                             const Eigen::Vector2d& mu, Eigen::Vector3d& r, const Eigen::Vector3d& start);

}  // namespace csim
