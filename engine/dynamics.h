// The smooth dynamics of a World, shared by every stepper (MuJoCo's smooth stage, Siconos'
// LagrangianDS): what the bodies and the forces on them are, with the contacts left out,
//   M v̇ = f(t, q, v),   f = f_loads(t, q, v) + f_internal(q) − C v,
// in the World's velocity coordinates (N, N·m):
//   f_loads     loads λ(t)·F at their points and gravity m·g, as Jᵀ·F, and the bodies' inertial
//               (gyroscopic) forces: the work of loads of the energy balance;
//   f_internal  the linear springs of world.h, and the internal forces of the elastic bodies
//               (−K u for linear elasticity, −∂W/∂q for a hyperelastic body): conservative, with
//               the potential elastic_energy(q);
//   −C v        viscous (Rayleigh) damping of the elastic bodies.
// Its tangents, sparse: the mass M (kg, kg·m²; constant), the stiffness K(q) = −∂f/∂q (N/m; the
// bodies' tangent and the springs' K = Σ k Jᵀ P J, without the geometric term of rotating attachment
// points: first order), the damping C = −∂f/∂v (N·s/m; constant, the gyroscopic term left out). And the
// rows of the equalities: the World's linear constraints and the prescriptions active at t
// (equality_rows), and the ties (TieRows, linearized at q by their owner).
//
// Steppers compose these, each with its own time discretization, and sum no force themselves: a force
// type added here reaches Moreau–Jean, the quasi-static stepper and IDA at once.
// Evaluated with no allocation once the work buffers are sized.
#pragma once

#include "engine/linear_algebra/linear_products.h"
#include "engine/springs.h"
#include "engine/world.h"

#include <utility>
#include <vector>

namespace csim {

// A finite-strain body that a stepper evaluates in a moving frame (the quasi-static stepper's bodies
// riding on a hub, reduced_coordinates.h): its positions in that frame, and its frame force turned to
// the world.
class BodyFrames {
 public:
  virtual ~BodyFrames() = default;
  virtual bool in_frame(int body) const = 0;
  virtual void frame_positions(const Vector& q, int body, Vector& positions) const = 0;
  virtual void add_turned_to_world(const Vector& q, int body, const Vector& frame_force, VectorRef f) const = 0;
};

// The equalities C v = target of a stepper at time t: the World's linear constraints, then the active
// prescriptions. Each row's terms: (position index, or −1 for a velocity without one, coefficient).
struct EqualityRows {
  Matrix rows;                                            // equalities × velocity components
  std::vector<std::vector<std::pair<int, double>>> terms;
  std::vector<int> prescriptions;                         // index in world.prescribed of each prescription row
};

class Dynamics {
 public:
  explicit Dynamics(const World& world);

  const World& world() const { return world_; }
  int size() const { return world_.velocity_size; }

  // f(t, q, v), all of it (sets f). loads (optional) gets f_loads alone, damping (optional) the
  // damping force −C v alone.
  void force(double t, const Vector& q, const Vector& v, Vector& f, Vector* loads = nullptr,
             Vector* damping = nullptr) const;

  // The parts, for steppers that weight them differently in time.
  void external(const Vector& q, double t, Vector& f) const;    // loads and gravity (sets f)
  // The same at two times (f_a at t_a, f_b at t_b), the loads' points taken at q once.
  void external(const Vector& q, double t_a, double t_b, Vector& f_a, Vector& f_b) const;
  void add_inertial_forces(const Vector& v, Vector& f) const;   // gyroscopic terms
  void add_internal_forces(const Vector& q, Vector& f) const;   // springs and bodies
  void add_spring_forces(const Vector& q, Vector& f) const { springs_.add_forces(q, f); }
  void add_body_internal_forces(const Vector& q, Vector& f) const;
  void add_damping_force(const Vector& v, Vector& f) const;     // f −= C v
  // The internal forces and, when stiffness is given, their tangent K = −∂f/∂q as triplets, in one
  // pass over the elements. A body that frames->in_frame holds is evaluated in its frame, its tangent
  // left in that frame, first in the triplets; returns where the world-frame triplets start.
  std::size_t add_internal_forces_and_tangent(const Vector& q, Vector& f, Triplets* stiffness,
                                              const BodyFrames* frames = nullptr) const;

  // Tangents.
  const SparseMatrix& mass() const { return mass_; }
  const SparseMatrix& damping() const { return damping_; }       // C
  // The bodies' K at u = 0, assembled at each call and not held here: the operators that need it keep
  // it, so that a large FE body's K is not held once more.
  SparseMatrix body_stiffness() const;
  void add_spring_stiffness(const Vector& q, Triplets& K) const { springs_.add_stiffness(q, K); }
  void spring_stiffness(const Vector& q, Matrix& K) const { springs_.stiffness(q, K); }  // dense, the springs only
  void add_stiffness(const Vector& q, Triplets& K) const;        // the bodies' tangent at q and the springs'
  void add_body_stiffness(const Vector& q, Triplets& K) const;   // the bodies' tangent at q alone
  // −∂f_loads/∂v: the gyroscopic forces' tangent, by differences on each rotating body (N·m·s).
  void add_inertial_tangent(const Vector& v, Triplets& D) const;

  // The rows of the equalities at time t (EqualityRows).
  void equality_rows(double t, EqualityRows& equalities) const;
  // The index in q of the coordinate whose rate velocity component i is, or −1 (a 3D rotation's).
  int position_of_velocity(int i) const { return position_of_velocity_[i]; }

  // J: springs and elastic bodies. A linear body's is ½ uᵀ(K u), with the K u that its internal force
  // at the same q (to the bit) then reuses (Body::stiffness_product).
  double elastic_energy(const Vector& q) const;
  double kinetic_energy(const Vector& v) const;  // J: ½ vᵀ M v
  // The same, with M x into Mx in the same pass over M (a large body's M is read once, not twice); each
  // the same to the bit as its own product.
  double kinetic_energy(const Vector& v, const Vector& x, Vector& Mx) const;

  // A linear World's K v (the bodies' and the springs') and M v, and M dv when dv is given, with the
  // bodies' K q, in one pass over K and M (linear_products.h); each of the bodies' products is the
  // separate product's to the bit. K q is kept as the bodies' products at q, which elastic_energy(q) and
  // the internal forces at q then read.
  void linear_products(const Vector& q, const Vector& v, const Vector* dv, Vector& Kv, Vector& Mv, Vector* Mdv) const;
  // Kv = K v alone, the bodies' and the springs' at q: linear_products' K v to the bit.
  void apply_linear_stiffness(const Vector& q, const Vector& v, Vector& Kv) const;

  bool has_elastic_bodies() const { return has_elastic_bodies_; }
  bool has_springs() const { return !world_.springs.empty(); }
  bool has_stiffness() const { return has_springs() || has_elastic_bodies_; }
  bool has_damping() const { return damping_.nonZeros() > 0; }
  bool nonlinear() const { return nonlinear_; }  // a body's internal force is nonlinear in q
  // True when K does not depend on q (springs only on translating points, linear bodies), so that an
  // iteration matrix can be factored once.
  bool constant_stiffness() const { return constant_spring_stiffness() && !nonlinear_; }
  // The same for the springs alone (a World of linear bodies may still have springs on rotating points).
  bool constant_spring_stiffness() const { return spring_stiffness_coordinates().empty(); }
  // The indices in q that the springs' K depends on: the orientation coordinates of the bodies with a
  // spring attached off their origin (none: the springs' K is constant). K is a function of these
  // alone, so that equal values give the same K to the bit.
  const std::vector<int>& spring_stiffness_coordinates() const { return springs_.stiffness_coordinates(); }
  // The springs' K at q is a function of their ends' Jacobian columns alone (m per unit velocity
  // component): columns gets them, end by end, so that equal values mean the same K to the bit even
  // where an orientation coordinate moved (a body turned by round-off).
  void spring_jacobian_columns(const Vector& q, std::vector<double>& columns) const {
    springs_.jacobian_columns(q, columns);
  }
  bool same_spring_jacobian_columns(const Vector& q, const std::vector<double>& columns) const {
    return springs_.same_jacobian_columns(q, columns);
  }

 private:
  const World& world_;
  Springs springs_;
  // Each load's Jacobian when it is the same at every q: at a rigid body's origin (its centre of mass),
  // the body's translations, its rotations' columns there being zero (their ±0 would leave the force as
  // it is); count 0 for a load whose Jacobian turns with its body.
  std::vector<PointJacobian> origin_load_jacobians_;
  std::vector<int> position_of_velocity_;
  SparseMatrix mass_, damping_;
  bool has_elastic_bodies_ = false;
  bool nonlinear_ = false;
  bool gyroscopic_ = false;  // a body has inertial forces
  mutable Vector work_;
  // The linear elastic bodies' K u (each in its velocity segment) at kept_positions_ (empty before the
  // first call), for the next call at the same q: a step's strain energy at q_{k+1} and the next step's
  // internal force share one product.
  bool has_linear_bodies_ = false;
  mutable Vector kept_positions_, kept_products_;
  mutable LinearProducts linear_products_;  // empty until first asked for (linear_product_table)
  const LinearProducts& linear_product_table() const;
  const Vector& linear_body_products(const Vector& q) const;
  // The bodies' weight (each in its velocity segment; empty without gravity), formed once: it does not
  // depend on q (Body::add_weight), and forming it reads an elastic body's M, or takes a rigid body's
  // Jacobian at its centre, at every step otherwise.
  Vector weight_;
};

}  // namespace csim
