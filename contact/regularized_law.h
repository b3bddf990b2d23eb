// Regularized (smooth) contact laws for the smooth reference integrator (SUNDIALS IDA), in the local
// frame of a contact point (contact_point.h: n from A to B, gap g > 0 open, u = v_B − v_A).
//
// Normal, penalty with linear damping:
//   F_n = max(0, k·(−g) − c·u_n)  when g < 0,   F_n = 0 otherwise        (N, on B along +n)
//   Error: the bodies interpenetrate; under a steady normal load F the penetration is F/k (m). The
//   contact is a spring-dashpot of natural frequency √(k/m) on a mass m, whose period the integrator
//   must resolve during impacts; with damping ratio ζ = c / (2√(k m)) a free impact rebounds with
//   e = exp(−ζπ/√(1−ζ²)) (ζ < 1) for the linear spring-dashpot, so ζ is chosen from the Newton
//   restitution of the scene's law; the no-tension clamp ends the contact a little before the dashpot
//   would, so the rebound is somewhat livelier than e for ζ near 1.
//
// Tangential, regularized Coulomb with regularization velocity ε (m/s), orthotropic M = diag(μ1, μ2):
//   F_t = −F_n · M (M u_t) / √(|M u_t|² + μ̄² ε²),   μ̄ = max(μ1, μ2)
//   (isotropic: F_t = −μ F_n u_t / √(|u_t|² + ε²); μ2 = 0: friction along t1 only, exactly).
//   Error: there is no true stick. A contact that should stick under a tangential load ρ μ F_n
//   (ρ < 1) creeps at |u_t| = ε ρ / √(1 − ρ²) (e.g. 0.58 ε at ρ = 0.5, 22 ε at ρ = 0.999); in slip
//   at speed |u_t| the friction force is short by the factor 1 − |u_t|/√(u_t² + ε²) ≈ ε²/(2 u_t²).
#pragma once

#include <Eigen/Dense>

namespace csim {

struct RegularizedContactLaw {
  double stiffness = 0.0;   // k, N/m
  double damping = 0.0;     // c, N·s/m
  double epsilon = 1e-6;    // ε, m/s
  Eigen::Vector2d mu = Eigen::Vector2d::Zero();
};

// Force on B in the local frame (F_n, F_t1, F_t2), N; dimension 2 leaves F_t2 = 0.
Eigen::Vector3d regularized_contact_force(const RegularizedContactLaw& law, double gap,
                                          const Eigen::Vector3d& local_velocity, int dimension);

// The derivatives of that force: ∂F/∂g (N/m) and ∂F/∂u (N·s/m, column j the derivative along u_j), zero
// where the contact is open (one-sided where it just closes: the open side's).
void regularized_contact_tangent(const RegularizedContactLaw& law, double gap, const Eigen::Vector3d& local_velocity,
                                 int dimension, Eigen::Vector3d& d_gap, Eigen::Matrix3d& d_velocity);

// Damping ratio ζ ∈ [0, 1] whose free linear impact rebounds with restitution e ∈ [0, 1].
double damping_ratio_for_restitution(double restitution);

}  // namespace csim
