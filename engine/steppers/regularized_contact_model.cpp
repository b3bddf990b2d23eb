#include "engine/steppers/regularized_contact_model.h"

#include <algorithm>
#include <cmath>

namespace csim {

namespace {

// The largest diagonal entry of A over a body's velocity components.
double largest_diagonal(const SparseMatrix& A, const BodyInstance& b) {
  double largest = 0.0;
  for (int i = b.velocity_offset; i < b.velocity_offset + b.body->velocity_size(); ++i)
    largest = std::max(largest, A.coeff(i, i));
  return largest;
}

}  // namespace

RegularizedContactModel::RegularizedContactModel(const Dynamics& dynamics, double penalty_stiffness,
                                                 double penalty_damping, double epsilon, double sample_step)
    : world_(dynamics.world()), detector_(dynamics.world()), sample_step_(sample_step) {
  double heaviest = 0.0;
  for (const BodyInstance& b : world_.bodies) heaviest = std::max(heaviest, b.body->mass());
  const SparseMatrix body_stiffness = dynamics.body_stiffness();
  for (const ContactLaw& law : world_.contact_laws) {
    RegularizedContactLaw regularized;
    double stiffest_node = 0.0, inverse_mass = 0.0;
    for (int body : {law.body_a, law.body_b}) {
      const BodyInstance& b = world_.bodies[body];
      if (b.body->fixed()) continue;
      if (b.body->elastic()) {
        stiffest_node = std::max(stiffest_node, largest_diagonal(body_stiffness, b));
        inverse_mass += 1.0 / largest_diagonal(dynamics.mass(), b);
      } else {
        inverse_mass += 1.0 / b.body->mass();
      }
    }
    const double k = penalty_stiffness > 0.0 ? penalty_stiffness
                     : stiffest_node > 0.0   ? kPenaltyRatio * stiffest_node
                                             : 1e8 * heaviest;
    regularized.stiffness = k;
    regularized.epsilon = epsilon;
    regularized.mu = law.mu;
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
  stored_energy_ = 0.0;
  if (detector_.empty()) return;
  detector_.detect(q, 0.0, contacts_, rows_);
  const int d = detector_.dimension();
  for (std::size_t i = 0; i < contacts_.size(); ++i) {
    ActiveContact& c = contacts_[i];
    const RegularizedContactLaw& law = laws_[c.law];
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    for (int k = 0; k < d; ++k) u(k) = rows_[d * i + k].dot(v);
    const Eigen::Vector3d force = regularized_contact_force(law, c.point.gap, u, d);
    for (int k = 0; k < d; ++k) rows_[d * i + k].scatter(force(k), f);
    if (c.point.gap < 0.0) stored_energy_ += 0.5 * law.stiffness * c.point.gap * c.point.gap;
    c.impulse = force * sample_step_;
    c.status = force(0) == 0.0 ? ContactStatus::open : ContactStatus::slip;
  }
  if (record) *record = contacts_;
}

// −f = −Σ_k h_kᵀ F_k(g, H v): ∂/∂v = −Σ h_kᵀ (∂F_k/∂u_l) h_l, ∂/∂q = −Σ h_kᵀ (∂F_k/∂g) h_n (the gap
// grows along the normal row; the frame's rotation is left out).
void RegularizedContactModel::add_tangent(const Vector& q, const Vector& v, Triplets& stiffness, Triplets& damping) {
  if (detector_.empty()) return;
  detector_.detect(q, 0.0, contacts_, rows_);
  const int d = detector_.dimension();
  Eigen::Vector3d d_gap;
  Eigen::Matrix3d d_velocity;
  for (std::size_t i = 0; i < contacts_.size(); ++i) {
    const ActiveContact& c = contacts_[i];
    if (!(c.point.gap < 0.0)) continue;
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    for (int k = 0; k < d; ++k) u(k) = rows_[d * i + k].dot(v);
    regularized_contact_tangent(laws_[c.law], c.point.gap, u, d, d_gap, d_velocity);
    const SparseRow& normal = rows_[d * i];
    for (int k = 0; k < d; ++k) {
      const SparseRow& row_k = rows_[d * i + k];
      for (int a = 0; a < row_k.count; ++a) {
        for (int b = 0; b < normal.count; ++b)
          if (d_gap(k) != 0.0)
            stiffness.emplace_back(row_k.index[a], normal.index[b], -row_k.value[a] * d_gap(k) * normal.value[b]);
        for (int l = 0; l < d; ++l) {
          if (d_velocity(k, l) == 0.0) continue;
          const SparseRow& row_l = rows_[d * i + l];
          for (int b = 0; b < row_l.count; ++b)
            damping.emplace_back(row_k.index[a], row_l.index[b], -row_k.value[a] * d_velocity(k, l) * row_l.value[b]);
        }
      }
    }
  }
}

}  // namespace csim
