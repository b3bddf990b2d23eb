// QuasiStatic's contact problem of a Newton iterate through its contact stage (quasi_static.h: "problem",
// "Penalty friction", "Complementarity"): the detection with the rows over z and the offsets c, penalty
// friction's terms, u = W r + b on the factored stiffness, and Signorini's law checked on the
// configuration the accepted iterate reaches.
#include "engine/steppers/quasi_static.h"

#include "engine/contact_stage/contact_solve.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace csim {

// The candidate contacts at q_j, all active, their rows over z (H_z = H T, the stage's operator) and
// offsets c (gap, slip since q_k).
void QuasiStatic::detect_contacts(const State& state, double t_next) {
  stage_.detect(q_, contact_distance_);
  for (int k = 0; k < stage_.candidate_count(); ++k) stage_.activate(k);
  stage_.gather_rows(nullptr, nullptr, t_next);
  q_detected_ = q_;
  const int m = stage_.problem().size();
  offset_.setZero(m);
  if (m == 0) return;
  world_.position_difference(q_, state.q, step_increment_);
  const std::vector<ActiveContact>& active = stage_.active();
  for (int i = 0; i < static_cast<int>(active.size()); ++i) {
    offset_(d_ * i) = active[i].point.gap;
    // The slip since the step start: the rows over q, before T.
    for (int k = 1; k < d_; ++k) offset_(d_ * i + k) = stage_.rows().dot(d_ * i + k, step_increment_);
  }
}

// A linear World's later iterate: the step start's contacts and rows, their offsets at q_j (the gap
// g_k + H_n (q_j ⊖ q_k), the slip H_t (q_j ⊖ q_k)), as detect_contacts would give them for a plane.
void QuasiStatic::shift_contact_offsets(const State& state) {
  const std::vector<ActiveContact>& active = stage_.active();
  if (active.empty()) return;
  world_.position_difference(q_, state.q, step_increment_);
  const ProblemRows& rows = stage_.rows();
  for (int i = 0; i < static_cast<int>(active.size()); ++i) {
    offset_(d_ * i) = active[i].point.gap + rows.dot(d_ * i, step_increment_);
    for (int k = 1; k < d_; ++k) offset_(d_ * i + k) = rows.dot(d_ * i + k, step_increment_);
  }
}

// Penalty friction's offset −γ φ_k on the tangential rows and its compliance at the warm start's normal
// forces (see the header).
void QuasiStatic::soften_friction(const State& state) {
  const std::vector<ActiveContact>& active = stage_.active();
  compliance_.setZero(stage_.problem().size());
  if (!penalty_friction_) return;
  compliance_normal_.setZero(active.size());
  warm_start(state.contacts, active, d_, stage_.problem().size(), start_impulse_);
  for (int i = 0; i < static_cast<int>(active.size()); ++i) {
    const ContactLaw& law = world_.contact_laws[active[i].law];
    const double start_normal = start_impulse_(d_ * i);
    const Eigen::Vector2d start_mu = law.mu_at(state.t);
    for (int k = 1; k < d_; ++k)  // φ_k from impulses: the step's h cancels in the ratio
      if (law.elastic_slip > 0.0 && start_normal > 0.0 && start_mu(k - 1) > 0.0)
        offset_(d_ * i + k) -= law.elastic_slip * start_impulse_(d_ * i + k) / (start_mu(k - 1) * start_normal);
  }
  set_compliance(stage_.impulses());
}

// compliance_ ← γ/(μ r_n) at the normal forces of r (m/N); a contact without a normal force there gets no
// friction. Returns the largest change of a normal force from the last call's, over the largest (0 when
// the compliance is exact for r).
double QuasiStatic::set_compliance(const Vector& r) {
  double change = 0.0, largest = 0.0;
  FrictionContactProblem& problem = stage_.problem();
  for (int i = 0; i < problem.contacts; ++i) {
    const ContactLaw& law = world_.contact_laws[stage_.active()[i].law];
    const double gamma = law.elastic_slip, normal = r(d_ * i);
    if (gamma <= 0.0) continue;
    const Eigen::Vector2d mu = law.mu_at(t_);  // detect_contacts' μ, which this may have zeroed
    largest = std::max(largest, normal);
    change = std::max(change, std::abs(normal - compliance_normal_(i)));
    compliance_normal_(i) = normal;
    for (int k = 1; k < d_; ++k) {
      problem.mu[i](k - 1) = normal > 0.0 ? mu(k - 1) : 0.0;
      compliance_(d_ * i + k) = normal > 0.0 && mu(k - 1) > 0.0 ? gamma / (mu(k - 1) * normal) : 0.0;
    }
  }
  return largest > 0.0 ? change / largest : 0.0;
}

// u = W r + b with the factored stiffness: W = H_z K⁻¹ H_zᵀ, b = H_z K⁻¹ f_aug + c (the stage's W, the
// operator's first half of the solve).
void QuasiStatic::assemble_problem() {
  FrictionContactProblem& problem = stage_.problem();
  const int m = problem.size();
  problem.W.resize(m, m);
  problem.b.resize(m);
  if (m == 0) return;
  stage_.form_delassus();
  operator_->load_term(f_aug_, problem.b);
  problem.b += offset_;
  problem.W.diagonal() += compliance_;
}

void QuasiStatic::update_contact_force() {
  contact_force_.setZero(f_.size());
  const Vector& r = stage_.impulses();
  for (int a = 0; a < r.size(); ++a) stage_.rows().scatter(a, r(a), contact_force_);
}

// complementarity_ ← the last iterate's violation of Signorini's law measured on the configuration it
// reaches, u = c + H_z Δz computed from Δz (not through W, whose round-off it would share), in metres: a
// penetration −u_n > 0, and an open gap u_n > 0 under a normal force r_n > 0, as min(u_n, r_n / max r_n · L)
// (a force at round-off of the largest does not count). Zero for an exact solution whatever W's scaling.
void QuasiStatic::measure_complementarity() {
  complementarity_ = 0.0;
  complementarity_contact_ = -1;
  const int nc = static_cast<int>(stage_.active().size());
  if (nc == 0) return;
  const Vector u = offset_ + operator_->reduced_rows() * dz_;
  const Vector& r = stage_.impulses();
  double largest = 0.0;
  for (int i = 0; i < nc; ++i) largest = std::max(largest, r(d_ * i));
  for (int i = 0; i < nc; ++i) {
    const double gap = u(d_ * i), force = r(d_ * i);
    double violation = std::max(0.0, -gap);
    if (gap > 0.0 && force > 0.0 && largest > 0.0) violation = std::min(gap, force / largest * length_);
    if (violation > complementarity_) {
      complementarity_ = violation;
      complementarity_contact_ = i;
      complementarity_gap_ = gap;
      complementarity_force_ = force;
    }
  }
}

// "" when the accepted iterate's contacts meet Signorini's law to failure_residual · L on the
// configuration it reaches (measure_complementarity), else the message that stops the step.
std::string QuasiStatic::complementarity_failure(double t_next) {
  measure_complementarity();
  max_complementarity_ = std::max(max_complementarity_, complementarity_);
  if (complementarity_ <= parameters_.failure_residual * length_) return "";
  const ActiveContact& contact = stage_.active()[complementarity_contact_];
  std::ostringstream message;
  message << "quasi-static: the contact solution at t = " << t_next << " s violates complementarity by "
          << complementarity_ << " m (tolerance contact_solver.failure_residual x L = "
          << parameters_.failure_residual * length_ << " m): a contact point of '"
          << world_.contact_laws[contact.law].name << "' ends with the gap " << complementarity_gap_
          << " m under the normal force " << complementarity_force_ << " N";
  if (!soft_unknowns_.empty()) message << " (the stiffness holds a mode of " << soft_directions() << " only by a proximal term)";
  return message.str();
}

}  // namespace csim
