// How the smooth integrator (IDA) obtains contact forces: from a regularized law of the state
// (RegularizedContactModel), or as the reactions of an exact Coulomb law whose stick/slip mode
// switches at located events (EventContactModel). Forces are generalized (N, N·m), in the velocity
// coordinates of the World.
#pragma once

#include "engine/state.h"

#include <vector>

namespace csim {

class SmoothContactModel {
 public:
  virtual ~SmoothContactModel() = default;

  // The contact force at (t, q, v), given the other forces f_applied (a reaction model needs them).
  // record (optional) receives the contacts, with impulse = local force × sample_step.
  virtual void force(double t, const Vector& q, const Vector& v, const Vector& f_applied, Vector& f_contact,
                     std::vector<ActiveContact>* record) = 0;

  // The tangent of −f_contact at (q, v), as triplets over velocity components: stiffness (∂/∂q, along
  // the velocity components' coordinates) and damping (∂/∂v). Models without one add nothing.
  virtual void add_tangent(const Vector& q, const Vector& v, Triplets& stiffness, Triplets& damping) {}

  // The energy stored in the contacts at the last force() (J): a penalty spring's ½ k g².
  virtual double stored_energy() const { return 0.0; }

  // Event functions for IDA's root finding, each to be caught when it decreases through zero.
  virtual int event_count() const { return 0; }
  virtual void events(double t, const Vector& q, const Vector& v, const Vector& f_applied, double* g) {}

  // Chooses the mode at the start and after each event (a root of `events`).
  virtual void choose_mode(double t, const Vector& q, const Vector& v, const Vector& f_applied) {}
};

}  // namespace csim
