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

  // This body's slice of the World's positions q.
  ConstVectorRef positions(const Vector& q) const { return q.segment(position_offset, body->position_size()); }
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

// Contact law between the shapes of two bodies: Coulomb friction (isotropic when mu(0) == mu(1);
// orthotropic with μ1 along friction_direction projected on the tangent plane, μ2 across it) and the
// Newton impact law with restitution e ∈ [0, 1].
struct ContactLaw {
  std::string name;
  int body_a = -1, body_b = -1;
  Eigen::Vector2d mu = Eigen::Vector2d::Zero();
  Eigen::Vector3d friction_direction = Eigen::Vector3d::Zero();
  double restitution = 0.0;
  // When one body is elastic: which of its features touch (deformable_surface.h).
  SurfaceFeatures features = SurfaceFeatures::nodes;
  bool isotropic() const { return mu(0) == mu(1); }
};

struct World {
  int dimension = 2;                                  // 2: plane z = 0, 3: space
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  // m/s²
  std::vector<BodyInstance> bodies;
  std::vector<Spring> springs;
  std::vector<Load> loads;
  std::vector<LinearConstraint> constraints;
  std::vector<ContactLaw> contact_laws;
  int position_size = 0;
  int velocity_size = 0;

  int body_index(const std::string& name) const {
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (bodies[i].name == name) return static_cast<int>(i);
    return -1;
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
