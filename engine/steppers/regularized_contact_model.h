// Contact forces from the regularized law of contact/regularized_law.h at every detected contact point
// with a negative gap: penalty with damping normal to the surface, regularized Coulomb along it.
//
// Default penalty stiffness, per contact law (integrator.penalty_stiffness = 0):
//   lumped bodies only: 1e8 × the heaviest body's mass (kg) in N/m, a contact frequency of 1e4 rad/s
//     for it and a penetration of about 1e-7 m under its own weight;
//   an elastic body in contact: kPenaltyRatio × the largest diagonal entry of its stiffness K (N/m), the
//     stiffness of its stiffest node. A node pressed by F sinks F/k_p into the surface, 1/kPenaltyRatio
//     = 100 times the displacement F/K_ii that the same force gives the node against the elements
//     around it: the penalty is a contact layer much softer than the elements. Its error is that
//     penetration and what it does to the distribution of the contact pressure, not the motion of the
//     body. A stiffer layer costs IDA dearly: the contact nodes rock on it at a higher frequency that
//     IDA must resolve (measured in bench/ida_fe.md). Set integrator.penalty_stiffness for a stiffer one.
// Default penalty damping, per law: the damping ratio ζ of the law's restitution (regularized_law.h)
// on the pair's effective mass, a node's (the largest diagonal entry of M) for an elastic body.
#pragma once

#include "contact/regularized_law.h"
#include "engine/contact_stage/contact_detector.h"
#include "engine/dynamics.h"
#include "engine/steppers/smooth_contact_model.h"
#include "engine/world.h"

namespace csim {

class RegularizedContactModel final : public SmoothContactModel {
 public:
  static constexpr double kPenaltyRatio = 0.01;

  // penalty_stiffness (N/m; 0 = the default above), penalty_damping (N·s/m; < 0 = from each law's
  // restitution), epsilon (m/s), sample_step (s, for impulses).
  RegularizedContactModel(const Dynamics& dynamics, double penalty_stiffness, double penalty_damping, double epsilon,
                          double sample_step);

  void force(double t, const Vector& q, const Vector& v, const Vector& f_applied, Vector& f_contact,
             std::vector<ActiveContact>* record) override;
  void add_tangent(const Vector& q, const Vector& v, Triplets& stiffness, Triplets& damping) override;
  double stored_energy() const override { return stored_energy_; }

  const RegularizedContactLaw& law(int index) const { return laws_[index]; }

 private:
  const World& world_;
  ContactDetector detector_;
  std::vector<RegularizedContactLaw> laws_;  // per contact law of the world
  double sample_step_;
  double stored_energy_ = 0.0;
  std::vector<ActiveContact> contacts_;
  std::vector<SparseRow> rows_;
};

}  // namespace csim
