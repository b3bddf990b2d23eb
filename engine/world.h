// What a scene describes, immutable once built: bodies and their shapes, springs, loads, linear
// kinematic constraints and contact laws. The mutable part of a simulation lives in State.
//
// Units: SI throughout (m, kg, s, N, rad). Generalized coordinates are concatenated body by body;
// `position_offset` / `velocity_offset` locate a body's slice in q and v.
#pragma once

#include "contact/deformable_surface.h"
#include "contact/shape.h"
#include "engine/bodies/body.h"
#include "engine/time_function.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace csim {

struct ShapeInstance {
  std::string name;
  Shape shape;
  Eigen::Isometry3d local_pose = Eigen::Isometry3d::Identity();  // shape frame in the body frame
};

struct BodyInstance {
  std::string name;
  std::unique_ptr<Body> body;
  Vector reference_position;  // q of the reference configuration (displacements are measured from it)
  Vector initial_position;    // q at t = 0
  Vector initial_velocity;    // v at t = 0
  int position_offset = 0;
  int velocity_offset = 0;
  std::vector<ShapeInstance> shapes;
  int group = -1;  // index in World::groups, −1: in no group (a body belongs to at most one)

  // This body's slice of the World's positions q.
  ConstVectorRef positions(const Vector& q) const { return q.segment(position_offset, body->position_size()); }
  // A bound on the speed of this body's material points at the World's velocities v (m/s): a rigid
  // body's |v| + |ω| R (R its bounding radius), a point's |v|, an elastic body's largest nodal component
  // × √dimension (every component at that speed). Convex in v. Not for a fixed body (no velocities).
  double point_speed_bound(const Vector& v, int dimension) const {
    const auto vb = v.segment(velocity_offset, body->velocity_size());
    if (body->elastic()) return vb.size() > 0 ? vb.cwiseAbs().maxCoeff() * std::sqrt(double(dimension)) : 0.0;
    const int translations = std::min<int>(dimension, static_cast<int>(vb.size()));
    double speed = vb.head(translations).norm();
    if (vb.size() > translations) speed += vb.tail(vb.size() - translations).norm() * body->bounding_radius;
    return speed;
  }
};

// A linear spring between material points of two bodies (or a body and the ground when body_b < 0).
// Its force is linear in the relative displacement of the two points from the reference
// configuration, d = (p_a − p_a,ref) − (p_b − p_b,ref):
//   isotropic (direction = 0):   force on A = −k d,            energy ½ k |d|²
//   along unit direction e:       force on A = −k e (e·d),      energy ½ k (e·d)²
// (the force on B is the opposite). k in N/m.
struct Spring {
  std::string name;
  int body_a = -1;
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  // body frame of A (m)
  int body_b = -1;                                    // -1: ground
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  // body frame of B (m); unused for the ground
  double stiffness = 0.0;                             // N/m
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();
};

// A force λ(t)·F (N, world frame) applied at a material point of a body (body frame, m), or a
// distributed load λ(t)·f given directly in the body's velocity coordinates (nodal_forces, N: the
// equivalent nodal forces of a pressure on a finite-element body's faces).
struct Load {
  std::string name;
  int body = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Vector nodal_forces;
  TimeFunction multiplier;
};

// Σ c_i (q_i − q_ref,i) = value over velocity components (translations, and the plane rotation);
// enforced at the end of every step (no drift). For 3D rotations only the velocity form holds.
struct LinearConstraint {
  std::string name;
  std::vector<std::pair<int, double>> terms;  // (global velocity index, coefficient)
  double value = 0.0;
};

// A velocity component of a lumped body whose displacement is prescribed: q_i(t) = q_ref,i + value(t)
// (m, or rad for a plane rotation), a table interpolated linearly. A ground moved along a path, a hub
// held at its centre, an imposed spin; a spin held during a press, then released (until). Honoured by
// the quasi-static stepper (the component leaves the unknowns) and by Moreau–Jean (an equality row
// holding it in position at each step's end); both report the reaction (the generalized force the
// prescription exerts, N or N·m; Moreau–Jean's includes the body's inertia).
struct PrescribedComponent {
  int body = -1;
  int component = -1;  // index in the body's velocity components
  TimeFunction value;  // m or rad (its table's second column is the value, not a multiplier)
  double until = std::numeric_limits<double>::infinity();  // s: then the component is released (free)
  bool active(double t) const { return t <= until; }
};

// Nodes of an elastic body tied to a rigid body: each node moves with the rigid body,
//   x_a = x_B + R_B R_B,ref⁻¹ (X_a − x_B,ref),
// exactly, whatever the rotation (a wheel's rim on its hub). X_a: the node's reference position,
// x_B, R_B: the rigid body's centre and rotation. The tied components leave the unknowns of the
// quasi-static stepper (reduced_coordinates.h).
struct RigidTie {
  std::string name;
  int elastic_body = -1;
  std::vector<int> nodes;  // mesh nodes
  int rigid_body = -1;     // a RigidBody2d or RigidBody3d
};

// A named set of bodies that contact laws may name as one side (contact_law_table.h).
struct BodyGroup {
  std::string name;
  std::vector<int> bodies;  // body indices, ascending
};

// Contact law between the shapes of two sides, each a body or a group of bodies: every pair of
// distinct bodies, one from each side, touches under it unless a more specific law names that pair
// (the precedence: contact_law_table.h). A group against itself pairs every two of its bodies.
// Coulomb friction (isotropic when mu(0) == mu(1);
// orthotropic with μ1 along friction_direction projected on the tangent plane, μ2 across it) and the
// Newton impact law with restitution e ∈ [0, 1].
struct ContactLaw {
  std::string name;
  // Each side is a body (body_x ≥ 0, group_x = −1) or a group (group_x ≥ 0, body_x = −1).
  int body_a = -1, body_b = -1;
  int group_a = -1, group_b = -1;
  Eigen::Vector2d mu = Eigen::Vector2d::Zero();
  Eigen::Vector3d friction_direction = Eigen::Vector3d::Zero();
  double restitution = 0.0;
  // When one body is elastic: which of its features touch (deformable_surface.h).
  SurfaceFeatures features = SurfaceFeatures::nodes;
  // μ ramped in linearly from 0 at mu_ramp_start to its value at mu_ramp_end (s); none when equal.
  double mu_ramp_start = 0.0, mu_ramp_end = 0.0;
  // Penalty friction (quasi-static stepper only): the elastic slip γ (m) at which a sticking contact's
  // tangential force reaches μ r_n (Abaqus' "allowable elastic slip"); 0: Coulomb's law, exact stick.
  double elastic_slip = 0.0;
  // false: the pairs this law governs never touch (scene key collide: false), e.g. two bodies a
  // constraint joins, or a pair a group's law would otherwise make; its other fields are unused.
  bool collides = true;
  bool isotropic() const { return mu(0) == mu(1); }
  bool between_bodies() const { return body_a >= 0 && body_b >= 0; }
  Eigen::Vector2d mu_at(double t) const {
    if (mu_ramp_end <= mu_ramp_start || t >= mu_ramp_end) return mu;
    if (t <= mu_ramp_start) return Eigen::Vector2d::Zero();
    return mu * ((t - mu_ramp_start) / (mu_ramp_end - mu_ramp_start));
  }
};

struct World {
  int dimension = 2;                                  // 2: plane z = 0, 3: space
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  // m/s²
  std::vector<BodyInstance> bodies;
  std::vector<Spring> springs;
  std::vector<Load> loads;
  std::vector<LinearConstraint> constraints;
  std::vector<PrescribedComponent> prescribed;
  std::vector<RigidTie> ties;
  std::vector<BodyGroup> groups;
  std::vector<ContactLaw> contact_laws;
  int position_size = 0;
  int velocity_size = 0;

  int body_index(const std::string& name) const {
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (bodies[i].name == name) return static_cast<int>(i);
    return -1;
  }
  // The largest bounding radius of a moving body (m; 1 when none is finite): Newton's length scale.
  double length_scale() const {
    double length = 0.0;
    for (const BodyInstance& b : bodies)
      if (!b.body->fixed() && std::isfinite(b.body->bounding_radius)) length = std::max(length, b.body->bounding_radius);
    return length > 0.0 ? length : 1.0;
  }
  // True when a prescription active at `from` is released by `to` (s).
  bool releases_prescription(double from, double to) const {
    for (const PrescribedComponent& p : prescribed)
      if (p.active(from) && !p.active(to)) return true;
    return false;
  }
  // d (velocity components) such that each body's slice of q1 = integrate_position(q0, d, 1): the
  // generalized displacement from q0 to q1 (m, rad).
  void position_difference(const Vector& q1, const Vector& q0, Vector& d) const {
    d.resize(velocity_size);
    for (const BodyInstance& b : bodies)
      b.body->position_difference(b.positions(q1), b.positions(q0),
                                  d.segment(b.velocity_offset, b.body->velocity_size()));
  }
  // Recomputes the offsets and sizes after bodies were added.
  void finalize_layout() {
    position_size = velocity_size = 0;
    for (auto& b : bodies) {
      b.position_offset = position_size;
      b.velocity_offset = velocity_size;
      position_size += b.body->position_size();
      velocity_size += b.body->velocity_size();
    }
  }
};

}  // namespace csim
