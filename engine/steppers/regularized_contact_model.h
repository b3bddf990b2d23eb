// Contact forces from the regularized law of contact/regularized_law.h at every detected contact point
// with a negative gap: penalty with damping normal to the surface, regularized Coulomb along it.
#pragma once

#include "contact/regularized_law.h"
#include "engine/contact_detector.h"
#include "engine/steppers/smooth_contact_model.h"
#include "engine/world.h"

namespace csim {

class RegularizedContactModel final : public SmoothContactModel {
 public:
  // penalty_stiffness (N/m; 0 = 1e8 × the heaviest mass), penalty_damping (N·s/m; < 0 = from each
  // law's restitution on the pair's effective mass), epsilon (m/s), sample_step (s, for impulses).
  RegularizedContactModel(const World& world, double penalty_stiffness, double penalty_damping, double epsilon,
                          double sample_step);

  void force(double t, const Vector& q, const Vector& v, const Vector& f_applied, Vector& f_contact,
             std::vector<ActiveContact>* record) override;

 private:
  const World& world_;
  ContactDetector detector_;
  std::vector<RegularizedContactLaw> laws_;  // per contact law of the world
  double sample_step_;
  std::vector<ActiveContact> contacts_;
  std::vector<SparseRow> rows_;
};

}  // namespace csim
