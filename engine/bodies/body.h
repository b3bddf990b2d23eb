// The body interface shared by every kind of body the stepper moves.
//
// Each body owns a slice of the generalized coordinates: `position_size()` entries of q (m, rad or a
// unit quaternion) and `velocity_size()` entries of v (m/s, rad/s). Lumped bodies have a constant
// mass matrix in these coordinates; material points are addressed by their coordinates in the body
// frame (m), and their world velocity is J(q)·v (point_jacobian).
//
// Displacements are measured from the reference configuration q_ref (the `position` of the scene);
// the initial state may differ from it (`initial_displacement`), as in SDND100 where the pad is
// released away from the spring's rest point.
//
// Contact asks a body, never its kind (Chrono's ChContactable): its contact features (the rigid shapes
// of its BodyInstance, or a deformable surface of nodes, segments and triangles), the Jacobian of a
// material point or of a surface point, its nodes (ties ride on them) and its rotation axes. Adding a
// body type touches the body and the scene reader only.
#pragma once

#include "contact/contact_point.h"
#include "contact/deformable_surface.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace csim {

class FeBody;

using Vector = Eigen::VectorXd;
using VectorRef = Eigen::Ref<Eigen::VectorXd>;
using ConstVectorRef = Eigen::Ref<const Eigen::VectorXd>;
using Matrix = Eigen::MatrixXd;
using Matrix3X = Eigen::Matrix<double, 3, Eigen::Dynamic>;
using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;

// The velocity of a material point as a short sum over the body's velocity components:
//   v_point = Σ_k column(k) · v[index[k]],  k < count ≤ 6
// (all six components of a rigid body, the two or three of a finite-element node), so that a contact
// or a spring on a body of 50 000 unknowns still costs a handful of numbers.
struct PointJacobian {
  PointJacobian() {}  // user-provided: `return {}` (a fixed body's point) fills nothing either
  int count = 0;
  // At most six for a rigid body, nine for a point of an elastic body's boundary triangle. Only the
  // first `count` are set (a Jacobian is made in every step, a dozen times: no fill of the rest).
  std::array<int, 9> index;                                           // body velocity components
  Eigen::Matrix<double, 3, 9> column;                                 // m/s per unit component
  void add(int component, const Eigen::Vector3d& direction) {
    index[count] = component;
    column.col(count++) = direction;
  }
  // rows.col(offset + index[k]) += sign · projection · column(k); projection is r × 3.
  template <typename Rows, typename Projection>
  void scatter(Rows&& rows, int offset, const Projection& projection, double sign) const {
    for (int k = 0; k < count; ++k) rows.col(offset + index[k]) += sign * (projection * column.col(k));
  }
};

// A material point's velocity along up to three world axes a_k: u_k = Σ_j value(k, j) · v[index[j]],
// value(k, j) = a_k · (column j of its PointJacobian). A contact's rows of H on one side, before the
// side's sign (contact_detector.h).
struct ProjectedJacobian {
  ProjectedJacobian() {}  // user-provided: nothing filled beyond what a body sets
  int count = 0;
  std::array<int, 9> index;            // body velocity components
  Eigen::Matrix<double, 3, 9> value;   // (axis, component), m/s per unit component along the axis
  bool ascending = false;              // index strictly increasing (a lumped body's 0, 1, …), known by its maker
};

// A deformable contact surface: the world positions of its nodes in the reference configuration (m)
// and the features built on them (segments, triangles, the nodes that may touch, a smoothed curve).
struct ContactSurface {
  std::vector<Eigen::Vector3d> reference_nodes;
  DeformableSurfaceGeometry geometry;
};

class Body {
 public:
  virtual ~Body() = default;

  virtual int position_size() const = 0;
  // How many of the coordinates, from the first, are lengths (m); the others are angles (rad) or a
  // quaternion's entries.
  virtual int translation_coordinates() const { return position_size(); }
  virtual int velocity_size() const = 0;
  bool fixed() const { return velocity_size() == 0; }

  // The body's (constant) mass matrix (kg, kg·m²) as triplets, its rows and columns shifted by offset
  // (the body's velocity offset in the World).
  virtual void add_mass(int offset, Triplets& mass) const = 0;

  // Elastic bodies (finite elements): constant stiffness (N/m) as triplets, the internal force
  // f_int = −K u at positions q (N), and the strain energy ½ uᵀKu (J). Rigid bodies have none.
  virtual void add_stiffness(int offset, Triplets& stiffness) const {}
  // Viscous damping C (N·s/m) as triplets, the damping force being −C v: Rayleigh damping of elastic
  // bodies. Other bodies have none.
  virtual void add_damping(int offset, Triplets& damping) const {}
  virtual void add_internal_force(const ConstVectorRef& q, VectorRef f) const {}
  virtual double strain_energy(const ConstVectorRef& q) const { return 0.0; }
  // A linear elastic body's (elastic() and not nonlinear()) K u at positions q (N), of which its
  // internal force is −K u and its strain energy ½ uᵀ(K u): Dynamics keeps the last product, which a
  // Moreau–Jean step asks for twice (the strain energy at q_{k+1}, the next step's force there).
  virtual void stiffness_product(const ConstVectorRef& q, VectorRef product) const {}
  // A linear elastic body's constant K in its velocity coordinates (N/m), where it holds one; null else.
  virtual const SparseMatrix* linear_stiffness() const { return nullptr; }
  virtual bool elastic() const { return false; }
  // Bodies whose internal force is nonlinear in q (finite-strain elements): the tangent stiffness
  // K_T(q) = −∂f_int/∂q (N/m) as triplets; linear bodies give their constant K.
  virtual bool nonlinear() const { return false; }
  virtual void add_tangent_stiffness(const ConstVectorRef& q, int offset, Triplets& stiffness) const {
    add_stiffness(offset, stiffness);
  }
  // Both at once, as a Newton iteration needs them (a finite-strain body then passes over its elements
  // once).
  virtual void add_internal_force_and_tangent(const ConstVectorRef& q, VectorRef f, int offset,
                                              Triplets& stiffness) const {
    add_internal_force(q, f);
    add_tangent_stiffness(q, offset, stiffness);
  }
  virtual double mass() const = 0;  // kg (0 for a fixed body)

  // World pose of the body frame for positions q (this body's slice).
  virtual Eigen::Isometry3d pose(const ConstVectorRef& q) const = 0;
  // World position of a material point given by its body-frame coordinates (for an elastic body: its
  // reference coordinates, a node's).
  virtual Eigen::Vector3d point_world(const ConstVectorRef& q, const Eigen::Vector3d& local) const {
    return pose(q) * local;
  }

  // World velocity of a material point = J v.
  virtual PointJacobian point_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& local) const = 0;
  // Both at once, J set in place: the two above to the bit. A body whose two share work (a rigid body's
  // turn) overrides it; a spring asks for both at every step.
  virtual Eigen::Vector3d point_kinematics(const ConstVectorRef& q, const Eigen::Vector3d& local,
                                           PointJacobian& J) const {
    J = point_jacobian(q, local);
    return point_world(q, local);
  }

  // Adds the weight in the uniform field g (m/s²) as a generalized force (N, N·m): m g at the centre of
  // mass of a rigid body (its Jacobian there is its translations, whatever its turn), M·(g per node) for
  // an elastic body (its exact consistent body force ∫ Nᵀ ρ g dV, with the whole M: a free node's
  // includes its coupling to fixed nodes, fe_body.h). The same at every q: Dynamics forms it once.
  virtual void add_weight(const ConstVectorRef& q, const Eigen::Vector3d& g, VectorRef f) const {
    const PointJacobian J = point_jacobian(q, Eigen::Vector3d::Zero());
    for (int k = 0; k < J.count; ++k) f(J.index[k]) += J.column.col(k).dot(mass() * g);
  }

  // q_next = q + h·v_theta, with the rotation part integrated on the rotation group where needed.
  virtual void integrate_position(const ConstVectorRef& q, const ConstVectorRef& v_theta, double h,
                                  VectorRef q_next) const = 0;

  // The coordinate (index in this body's q) that velocity component c is the rate of, or −1 when there
  // is none (a 3D rigid body's rotation: its coordinates are a quaternion).
  virtual int coordinate_of(int c) const { return c; }

  // The increment d of the velocity components that takes q0 to q1: q1 = integrate_position(q0, d, 1)
  // (m, rad). q1 − q0, except for the quaternion of a 3D rigid body.
  virtual void position_difference(const ConstVectorRef& q1, const ConstVectorRef& q0, VectorRef d) const {
    d = q1 - q0;
  }

  // dq/dt for velocities v (smooth integrators); the coordinates' rate equals v except for the
  // quaternion of a 3D rigid body.
  virtual void position_rate(const ConstVectorRef& q, const ConstVectorRef& v, VectorRef q_dot) const {
    q_dot = v;
  }

  // Velocity-dependent generalized force that is not a load (gyroscopic terms), N and N·m.
  virtual void add_inertial_force(const ConstVectorRef& v, VectorRef f) const {}
  virtual bool has_inertial_force() const { return false; }
  // True when position_rate is v itself (every body but a 3D rigid body, whose rotation is a quaternion).
  virtual bool position_rate_is_velocity() const { return true; }

  // Index of a named velocity component ("x", "y", "z", "rx", "ry", "rz"), or -1.
  virtual int velocity_index(const std::string& component) const = 0;

  // ---- Contact features and their Jacobians ----

  // The deformable surface this body touches through, or nullopt when it touches through the rigid
  // shapes of its BodyInstance (rigid bodies, point masses, fixed bodies). smoothed: also build the
  // smooth curve through the boundary nodes (a contact law asks for SurfaceFeatures::smoothed).
  virtual std::optional<ContactSurface> contact_surface(bool smoothed) const { return std::nullopt; }
  // The world positions (m) at positions q of the listed nodes of the contact surface, into positions
  // indexed as reference_nodes and sized to all of them; the other entries are kept (a detection
  // refreshes the nodes its surface's geometry names, a small part of a large body's).
  virtual void surface_node_positions(const ConstVectorRef& q, const std::vector<int>& nodes,
                                      std::vector<Eigen::Vector3d>& positions) const {
    positions.clear();
  }
  // The Jacobian of a point of the contact surface given by its nodes and weights (a contact's
  // SurfacePoint): Σ weight · (the node's columns). Empty for a body without a contact surface.
  virtual PointJacobian surface_point_jacobian(const ConstVectorRef& q, const SurfacePoint& point) const { return {}; }
  // The Jacobian of the material point at world position x (m): a contact point on one of the body's shapes.
  PointJacobian world_point_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& x) const {
    return point_jacobian(q, pose(q).inverse() * x);
  }
  // That Jacobian projected on axes[0 .. axis_count) (axis_count ≤ 3). Lumped bodies write it from the
  // lever arm x − (their origin) in world axes, without the inverse pose and the body-frame point
  // (the same values to round-off, at a fifth of the cost); the others project world_point_jacobian.
  virtual void project_world_point_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& x,
                                            const Eigen::Vector3d* const* axes, int axis_count,
                                            ProjectedJacobian& out) const {
    const PointJacobian J = world_point_jacobian(q, x);
    out.count = J.count;
    out.ascending = false;  // not known: the rows check
    for (int j = 0; j < J.count; ++j) {
      out.index[j] = J.index[j];
      for (int k = 0; k < axis_count; ++k) out.value(k, j) = axes[k]->dot(J.column.col(j));
    }
  }

  // The same projection for the material point at the world lever arm r from the body's origin (m): a
  // contact point whose arm its shape knows (ContactPoint::arm_a), so that the position's rounding in
  // x − origin does not reach the rows. The default forms the world point.
  virtual void project_lever_arm_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& r,
                                          const Eigen::Vector3d* const* axes, int axis_count,
                                          ProjectedJacobian& out) const {
    project_world_point_jacobian(q, pose(q).translation() + r, axes, axis_count, out);
  }

  // Nodes of a body discretized by nodes (an elastic body's mesh nodes); none for a lumped body.
  virtual int node_count() const { return 0; }
  // Displacement components per node (2 in plane scenes, 3 in space).
  virtual int node_components() const { return 0; }
  // A node's reference position (m).
  virtual Eigen::Vector3d node_reference(int node) const { return Eigen::Vector3d::Zero(); }
  // The index among this body's velocity components of node's displacement component c, or −1 when
  // the component is fixed.
  virtual int node_velocity_index(int node, int c) const { return -1; }

  // The velocity components that are rotation rates (rad/s) with their axes in the body frame: (2, e_z)
  // for a plane rigid body, (3, e_x), (4, e_y), (5, e_z) for a rigid body in space; none for a body
  // that does not rotate as a whole.
  virtual std::vector<std::pair<int, Eigen::Vector3d>> rotation_axes() const { return {}; }

  // The finite-element body itself, or nullptr: for what needs its mesh and fields rather than its
  // contact features (output writers, the scene reader's node and face sets, pressures).
  virtual const FeBody* finite_elements() const { return nullptr; }

  // Radius of a sphere about the body origin that contains all its shapes (m), for speed bounds.
  double bounding_radius = 0.0;
};

}  // namespace csim
