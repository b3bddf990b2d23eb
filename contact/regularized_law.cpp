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

double damping_ratio_for_restitution(double restitution) {
  if (restitution >= 1.0) return 0.0;
  if (restitution <= 0.0) return 1.0;
  const double log_e = std::log(restitution);
  return -log_e / std::sqrt(M_PI * M_PI + log_e * log_e);
}

}  // namespace csim
