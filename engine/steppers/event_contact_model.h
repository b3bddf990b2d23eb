// Exact Coulomb friction for the smooth integrator, without regularization: the contact points that
// are closed at t = 0 stay closed (bilateral normal constraints), and the interface is in one of two
// modes, switched at events that IDA locates to its root-finding precision:
//   slip(d)  the points slide with the direction d (unit, in the tangent plane, fixed during the phase);
//            each carries the friction force −λ_n M² d / |M d| (M = diag(μ1, μ2); isotropic: −μ λ_n d);
//            event: the sliding velocity u_t·d of the first point falls to zero;
//   stick    the tangential velocity is held at zero along every direction with μ_i > 0;
//            event: the resultant tangential reaction reaches the cone, |M⁻¹ Λ_t| = Λ_n.
// At each event (and at t = 0) the mode is chosen from the stick reactions: stick if they lie in the
// cone, otherwise slip along the reaction's opposite. The reactions λ solve, at the acceleration level,
//   (X P G) λ = −X P f,   P = N (NᵀMN)⁻¹ Nᵀ,   f_contact = G λ,
// with X the constrained rows (normal, plus tangential in stick) and G their force directions (in slip
// the friction rides on the normal columns). A least-squares solve gives the minimum-norm split where
// the points are redundant (a box on a plane); the resultants are unique.
//
// Scope (refused before the first step: by IdaIntegrator::unsupported, and here for the closed
// contact): one contact law, between a moving body and a fixed one, closed at t = 0, whose points slide together (a translating interface) and never lift
// off (a negative normal reaction stops the run with a message). The term Ḣv of a rotating contact
// frame is neglected: exact for translating bodies, which is what this reference mode is for.
#pragma once

#include "engine/contact_stage/contact_detector.h"
#include "engine/steppers/smooth_contact_model.h"
#include "engine/world.h"

namespace csim {

class EventContactModel final : public SmoothContactModel {
 public:
  // projected_inverse_mass: P above (velocity_size²); sample_step (s) for the recorded impulses.
  EventContactModel(const World& world, const Vector& q0, const Matrix& projected_inverse_mass,
                    double sample_step);

  void force(double t, const Vector& q, const Vector& v, const Vector& f_applied, Vector& f_contact,
             std::vector<ActiveContact>* record) override;
  int event_count() const override { return 2; }  // mode change, lift-off
  void events(double t, const Vector& q, const Vector& v, const Vector& f_applied, double* g) override;
  void choose_mode(double t, const Vector& q, const Vector& v, const Vector& f_applied) override;

  bool sticking() const { return stick_; }

 private:
  struct Point {
    ContactPoint point;             // as detected at t = 0 (frame in the world)
    Eigen::Vector3d local;          // material point on the moving body (body frame)
  };
  // Rows at q: normal (np × n) and tangential (np·(d−1) × n), u = rows·v.
  void rows_at(const Vector& q);
  // Reactions for the current mode (or stick when `as_stick`): fills lambda_ and f_contact_.
  void reactions(const Vector& f_applied, bool as_stick);
  Eigen::Vector2d friction_direction() const;  // M² d / |M d| in tangent coordinates

  const World& world_;
  Matrix P_;
  int moving_ = -1;                 // the moving body
  int law_ = -1;
  int d_;                           // rows per point: 2 (plane) or 3
  Eigen::Vector2d mu_;
  std::vector<Point> points_;
  double sample_step_;
  bool stick_ = true;
  Eigen::Vector2d slip_direction_ = Eigen::Vector2d::UnitX();  // d, tangent coordinates

  Matrix normal_rows_, tangent_rows_, X_, G_;
  Vector lambda_, f_contact_;
};

}  // namespace csim
