// The engine's side of contact detection, shared by every stepper: it owns the CollisionWorld (only
// for bodies that a contact law's side holds: a body in no law touches nothing), keeps the poses of the moving shapes up to date, and turns the
// detected points into contacts between bodies with their law, their frame (aligned with the law's
// friction direction when it is anisotropic) and their rows of H:
//   u = H v,  u = [n t1 (t2)]ᵀ (v_B(p_b) − v_A(p_a))   (m/s; n from the point's body A to body B).
#pragma once

#include "contact/collision_world.h"
#include "engine/contact_stage/contact_law_table.h"
#include "engine/linear_algebra/sparse_row.h"
#include "engine/state.h"
#include "engine/world.h"

#include <memory>
#include <vector>

namespace csim {

class ContactDetector {
 public:
  explicit ContactDetector(const World& world);
  ~ContactDetector();
  ContactDetector(const ContactDetector&) = delete;
  ContactDetector& operator=(const ContactDetector&) = delete;

  bool empty() const { return collision_ == nullptr; }
  int dimension() const { return dimension_; }  // rows per contact: 2 in plane scenes, 3 in space

  // Contacts with gap ≤ margin (m) at positions q: `contacts` gets one entry per point (law, bodies,
  // point with its frame), `rows` their H rows: contact i owns rows [dimension·i, dimension·(i+1)).
  void detect(const Vector& q, double margin, std::vector<ActiveContact>& contacts, std::vector<SparseRow>& rows);

  // The Jacobian of a contact's point on one side: on an elastic body its surface point (nodes and
  // weights), otherwise the body's material point under the world point.
  PointJacobian side_jacobian(const Vector& q, int object, const ContactPoint& c, const Eigen::Vector3d& world_point) const;

  // A contact detected at q0 carried to the positions q0 ⊕ dq (dq in velocity components, small): each
  // side's point moves with its material point (its Jacobian at q0 times dq), the gap by the normal
  // component of their relative motion (the gap the linearized contact problem solves for). The frame
  // is kept: the contact's impulse or force is given in it.
  void move_contact(const Vector& q0, const Vector& dq, ContactPoint& c) const;

  // Bodies asleep (engine/steppers/sleeping_islands.h: one entry a body, nonzero while asleep; null:
  // none), read at every detection: a pair of two resting bodies (asleep or fixed) is not examined, and
  // an asleep body's pose is not updated (it is held).
  void set_asleep(const std::vector<char>* asleep) { asleep_ = asleep; }

  // The bound on how far any material point moves in time h at velocities v (m), for margins: convex in
  // v (a sum of norms, or a largest entry, a body; the largest of the bodies').
  double travel_bound(const Vector& v, double h) const;

 private:
  // The law under which bodies a and b touch, −1 when none does or the law that governs them says
  // they never collide (ContactLaw::collides).
  int touching_law(int a, int b) const {
    if (asleep_ && resting(a) && resting(b)) return -1;  // guarded: no cost a pair when none sleeps
    const int l = laws_.law(a, b);
    return l >= 0 && world_.contact_laws[l].collides ? l : -1;
  }
  // The rows of a contact between shapes of two distinct bodies (no deformable surface): each side's
  // point Jacobian projected on the contact's axes by its body (Body::project_world_point_jacobian, or
  // project_lever_arm_jacobian with the contact's arm where its shape knows it), the same rows as
  // contact_rows' to round-off.
  void shape_contact_rows(const Vector& q, int body_a, int body_b, const ContactPoint& c, SparseRow* rows) const;

  // Fixed, or asleep (set_asleep).
  bool resting(int body) const { return world_.bodies[body].body->fixed() || (asleep_ && (*asleep_)[body]); }

  const World& world_;
  int dimension_;
  const std::vector<char>* asleep_ = nullptr;
  std::unique_ptr<CollisionWorld> collision_;
  std::vector<int> object_body_;   // collision object → body index
  std::vector<int> object_shape_;  // collision object → shape index in its body, −1 for a deformable surface
  std::vector<char> shape_at_origin_;  // collision object → its shape's origin is its body's (no offset)
  // Each deformable surface's node positions by collision object (its body's nodes; the surface's kept current).
  std::vector<std::vector<Eigen::Vector3d>> node_positions_;
  ContactLawTable laws_;           // body pair → contact law index or −1
  std::vector<ContactPoint> points_;
};

// Rows of one contact point between bodies A and B into rows (dimension × n), from the Jacobians of
// the touching points of A and B (empty for a fixed body).
void contact_rows(const World& world, int body_a, const PointJacobian& point_a, int body_b,
                  const PointJacobian& point_b, const ContactPoint& c, int dimension, SparseRow* rows);

}  // namespace csim
