#include "engine/steppers/event_contact_model.h"

#include "engine/steppers/stepper.h"

#include <cmath>
#include <sstream>

namespace csim {

EventContactModel::EventContactModel(const World& world, const Vector& q0, const Matrix& projected_inverse_mass,
                                     double sample_step)
    : world_(world), P_(projected_inverse_mass), d_(world.dimension == 2 ? 2 : 3), sample_step_(sample_step) {
  // One law between a moving and a fixed body: IdaIntegrator::unsupported refused the other Worlds.
  law_ = 0;
  const ContactLaw& law = world.contact_laws[0];
  mu_ = law.mu;
  moving_ = world.bodies[law.body_a].body->fixed() ? law.body_b : law.body_a;

  ContactDetector detector(world);
  std::vector<ActiveContact> contacts;
  std::vector<SparseRow> rows;
  detector.detect(q0, 1e-9, contacts, rows);
  const BodyInstance& body = world.bodies[moving_];
  for (const ActiveContact& c : contacts) {
    Point p;
    p.point = c.point;
    // Frame with the normal pointing from the fixed body into the moving one.
    const bool moving_is_b = c.body_b == moving_;
    if (!moving_is_b) {
      p.point.normal = -p.point.normal;
      p.point.t1 = -p.point.t1;  // keeps (n, t1, t2) right-handed
    }
    const Eigen::Vector3d& on_moving = moving_is_b ? c.point.point_b : c.point.point_a;
    p.local = body.body->pose(body.positions(q0)).inverse() * on_moving;
    points_.push_back(p);
  }
  if (points_.empty())
    throw RunError(0.0, "integrator.type: ida-events needs the contact of law '" + law.name +
                            "' closed at t = 0 (no point within 1e-9 m); use ida or moreau-jean for contacts that open");
}

void EventContactModel::rows_at(const Vector& q) {
  const int np = static_cast<int>(points_.size());
  const int n = world_.velocity_size;
  const BodyInstance& b = world_.bodies[moving_];
  normal_rows_.setZero(np, n);
  tangent_rows_.setZero(np * (d_ - 1), n);
  for (int i = 0; i < np; ++i) {
    const PointJacobian J = b.body->point_jacobian(b.positions(q), points_[i].local);
    const ContactPoint& c = points_[i].point;
    J.scatter(normal_rows_.row(i), b.velocity_offset, c.normal.transpose(), 1.0);
    J.scatter(tangent_rows_.row((d_ - 1) * i), b.velocity_offset, c.t1.transpose(), 1.0);
    if (d_ == 3) J.scatter(tangent_rows_.row(2 * i + 1), b.velocity_offset, c.t2.transpose(), 1.0);
  }
}

Eigen::Vector2d EventContactModel::friction_direction() const {
  Eigen::Vector2d direction = slip_direction_;
  if (d_ == 2) direction(1) = 0.0;
  const Eigen::Vector2d scaled = mu_.cwiseProduct(direction);
  const double norm = scaled.norm();
  return norm > 0.0 ? Eigen::Vector2d(mu_.cwiseProduct(scaled) / norm) : Eigen::Vector2d::Zero();
}

void EventContactModel::reactions(const Vector& f_applied, bool as_stick) {
  const int np = static_cast<int>(points_.size());
  const int n = world_.velocity_size;
  if (as_stick) {
    // Constrained: normals, and the tangential directions that carry friction.
    std::vector<int> active;
    for (int i = 0; i < np; ++i)
      for (int k = 0; k < d_ - 1; ++k)
        if (mu_(k) > 0.0) active.push_back((d_ - 1) * i + k);
    X_.resize(np + static_cast<int>(active.size()), n);
    X_.topRows(np) = normal_rows_;
    for (std::size_t j = 0; j < active.size(); ++j) X_.row(np + j) = tangent_rows_.row(active[j]);
    G_ = X_.transpose();
  } else {
    X_ = normal_rows_;
    const Eigen::Vector2d m = friction_direction();
    G_ = normal_rows_.transpose();
    for (int i = 0; i < np; ++i)
      for (int k = 0; k < d_ - 1; ++k) G_.col(i) -= m(k) * tangent_rows_.row((d_ - 1) * i + k).transpose();
  }
  const Matrix A = X_ * P_ * G_;
  const Vector rhs = -(X_ * (P_ * f_applied));
  lambda_ = A.completeOrthogonalDecomposition().solve(rhs);
  f_contact_ = G_ * lambda_;
}

void EventContactModel::force(double, const Vector& q, const Vector&, const Vector& f_applied, Vector& f,
                              std::vector<ActiveContact>* record) {
  rows_at(q);
  reactions(f_applied, stick_);
  f = f_contact_;
  if (!record) return;
  record->clear();
  const int np = static_cast<int>(points_.size());
  std::vector<Eigen::Vector3d> local(np, Eigen::Vector3d::Zero());  // (λ_n, λ_t1, λ_t2) per point
  for (int i = 0; i < np; ++i) local[i](0) = lambda_(i);
  if (stick_) {
    int row = np;  // the tangential reactions follow the normal ones, point by point (see reactions)
    for (int i = 0; i < np; ++i)
      for (int k = 0; k < d_ - 1; ++k)
        if (mu_(k) > 0.0) local[i](1 + k) = lambda_(row++);
  } else {
    const Eigen::Vector2d m = friction_direction();
    for (int i = 0; i < np; ++i) local[i].segment(1, d_ - 1) = -lambda_(i) * m.head(d_ - 1);
  }
  const ContactLaw& law = world_.contact_laws[law_];
  for (int i = 0; i < np; ++i) {
    ActiveContact& c = record->emplace_back();
    c.point = points_[i].point;
    c.law = law_;
    c.body_b = moving_;  // the frame's normal points into the moving body, which is its "B"
    c.body_a = law.body_a == moving_ ? law.body_b : law.body_a;
    c.impulse = local[i] * sample_step_;
    c.status = stick_ ? ContactStatus::stick : ContactStatus::slip;
  }
}

void EventContactModel::events(double, const Vector& q, const Vector& v, const Vector& f_applied, double* g) {
  rows_at(q);
  reactions(f_applied, stick_);
  const int np = static_cast<int>(points_.size());
  if (stick_) {
    // Cone margin of the resultant: Λ_n − |M⁻¹ Λ_t| over the directions with friction.
    const double normal = lambda_.head(np).sum();
    Eigen::Vector2d tangential = Eigen::Vector2d::Zero();
    int row = np;
    for (int i = 0; i < np; ++i)
      for (int k = 0; k < d_ - 1; ++k)
        if (mu_(k) > 0.0) tangential(k) += lambda_(row++) / mu_(k);
    g[0] = normal - tangential.norm();
  } else {
    Eigen::Vector2d u = Eigen::Vector2d::Zero();
    for (int k = 0; k < d_ - 1; ++k) u(k) = tangent_rows_.row(k).dot(v);
    g[0] = u.dot(slip_direction_);
  }
  g[1] = lambda_.head(np).minCoeff();
}

void EventContactModel::choose_mode(double t, const Vector& q, const Vector& v, const Vector& f_applied) {
  rows_at(q);
  const int np = static_cast<int>(points_.size());
  Eigen::Vector2d u = Eigen::Vector2d::Zero();
  for (int k = 0; k < d_ - 1; ++k) u(k) = tangent_rows_.row(k).dot(v);
  const double speed_scale = 1e-9 * std::max(1.0, v.norm());
  if (u.norm() > speed_scale) {  // moving: slip along the motion
    stick_ = false;
    slip_direction_ = u.normalized();
    return;
  }
  reactions(f_applied, true);
  Eigen::Vector2d tangential = Eigen::Vector2d::Zero(), resultant = Eigen::Vector2d::Zero();
  int row = np;
  for (int i = 0; i < np; ++i)
    for (int k = 0; k < d_ - 1; ++k)
      if (mu_(k) > 0.0) {
        resultant(k) += lambda_(row);
        tangential(k) += lambda_(row++) / mu_(k);
      }
  const double normal = lambda_.head(np).sum();
  const bool in_cone = tangential.norm() <= normal * (1.0 + 1e-12);
  if (in_cone) {
    stick_ = true;
  } else {
    stick_ = false;
    slip_direction_ = (-resultant).normalized();  // the reaction resists the motion about to start
    reactions(f_applied, false);
  }
  if ((lambda_.head(np).array() < 0.0).any()) {
    std::ostringstream message;
    message << "ida-events: the contact of law '" << world_.contact_laws[law_].name << "' would open at t = " << t
            << " s (negative normal reaction in " << (stick_ ? "stick" : "slip")
            << "); this mode supports persistent contact only";
    throw RunError(t, message.str());
  }
}

}  // namespace csim
