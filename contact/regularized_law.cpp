#include "contact/regularized_law.h"

#include <cmath>

namespace csim {

Eigen::Vector3d regularized_contact_force(const RegularizedContactLaw& law, double gap,
                                          const Eigen::Vector3d& u, int dimension) {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  if (!(gap < 0.0)) return force;
  const double normal = law.stiffness * (-gap) - law.damping * u(0);
  if (!(normal > 0.0)) return force;
  force(0) = normal;
  const double mu_max = law.mu.maxCoeff();
  if (!(mu_max > 0.0)) return force;
  Eigen::Vector2d scaled = law.mu.cwiseProduct(u.segment<2>(1));  // M u_t
  if (dimension == 2) scaled(1) = 0.0;
  const double denominator = std::sqrt(scaled.squaredNorm() + mu_max * mu_max * law.epsilon * law.epsilon);
  force.segment<2>(1) = -normal * law.mu.cwiseProduct(scaled) / denominator;
  return force;
}

void regularized_contact_tangent(const RegularizedContactLaw& law, double gap, const Eigen::Vector3d& u,
                                 int dimension, Eigen::Vector3d& d_gap, Eigen::Matrix3d& d_velocity) {
  d_gap.setZero();
  d_velocity.setZero();
  if (!(gap < 0.0)) return;
  const double normal = law.stiffness * (-gap) - law.damping * u(0);
  if (!(normal > 0.0)) return;
  d_gap(0) = -law.stiffness;
  d_velocity(0, 0) = -law.damping;
  const double mu_max = law.mu.maxCoeff();
  if (!(mu_max > 0.0)) return;
  // F_t = −F_n M a / s with a = M u_t, s = √(|a|² + μ̄²ε²): ∂F_t/∂u_t = −F_n M (I/s − a aᵀ/s³) M, and
  // F_t is proportional to F_n along g and u_n.
  Eigen::Matrix2d M = law.mu.asDiagonal();
  if (dimension == 2) M(1, 1) = 0.0;
  const Eigen::Vector2d a = M * u.segment<2>(1);
  const double s = std::sqrt(a.squaredNorm() + mu_max * mu_max * law.epsilon * law.epsilon);
  const Eigen::Vector2d tangential = -normal * M * a / s;
  d_gap.segment<2>(1) = tangential / normal * d_gap(0);
  d_velocity.block<2, 1>(1, 0) = tangential / normal * d_velocity(0, 0);
  d_velocity.block<2, 2>(1, 1) = -normal * M * (Eigen::Matrix2d::Identity() / s - a * a.transpose() / (s * s * s)) * M;
}

double damping_ratio_for_restitution(double restitution) {
  if (restitution >= 1.0) return 0.0;
  if (restitution <= 0.0) return 1.0;
  const double log_e = std::log(restitution);
  return -log_e / std::sqrt(M_PI * M_PI + log_e * log_e);
}

}  // namespace csim
