#include "engine/steppers/regularized_contact_model.h"

#include <cmath>

namespace csim {

RegularizedContactModel::RegularizedContactModel(const World& world, double penalty_stiffness,
                                                 double penalty_damping, double epsilon, double sample_step)
    : world_(world), detector_(world), sample_step_(sample_step) {
  double heaviest = 0.0;
  for (const BodyInstance& b : world.bodies) heaviest = std::max(heaviest, b.body->mass());
  const double k = penalty_stiffness > 0.0 ? penalty_stiffness : 1e8 * heaviest;
  for (const ContactLaw& law : world.contact_laws) {
    RegularizedContactLaw regularized;
    regularized.stiffness = k;
    regularized.epsilon = epsilon;
    regularized.mu = law.mu;
    double inverse_mass = 0.0;
    for (int body : {law.body_a, law.body_b})
      if (!world.bodies[body].body->fixed()) inverse_mass += 1.0 / world.bodies[body].body->mass();
    const double effective_mass = inverse_mass > 0.0 ? 1.0 / inverse_mass : 0.0;
    regularized.damping = penalty_damping >= 0.0
                              ? penalty_damping
                              : 2.0 * damping_ratio_for_restitution(law.restitution) * std::sqrt(k * effective_mass);
    laws_.push_back(regularized);
  }
}

void RegularizedContactModel::force(double, const Vector& q, const Vector& v, const Vector&, Vector& f,
                                    std::vector<ActiveContact>* record) {
  f.setZero(world_.velocity_size);
  if (detector_.empty()) return;
  detector_.detect(q, 0.0, contacts_, rows_);
  const int d = detector_.dimension();
  for (std::size_t i = 0; i < contacts_.size(); ++i) {
    ActiveContact& c = contacts_[i];
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    for (int k = 0; k < d; ++k) u(k) = rows_[d * i + k].dot(v);
    const Eigen::Vector3d force = regularized_contact_force(laws_[c.law], c.point.gap, u, d);
    for (int k = 0; k < d; ++k) rows_[d * i + k].scatter(force(k), f);
    c.impulse = force * sample_step_;
    c.status = force(0) == 0.0 ? ContactStatus::open : ContactStatus::slip;
  }
  if (record) *record = contacts_;
}

}  // namespace csim
