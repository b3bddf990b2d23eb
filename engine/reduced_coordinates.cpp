#include "engine/reduced_coordinates.h"

#include "engine/bodies/fe_body.h"
#include "engine/bodies/rigid_body_2d.h"

#include <cmath>
#include <stdexcept>

namespace csim {

namespace {

Eigen::Matrix2d rotation(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Eigen::Matrix2d R;
  R << c, -s, s, c;
  return R;
}

}  // namespace

ReducedCoordinates::ReducedCoordinates(const World& world) : world_(world) {
  const int n = world.position_size;
  if (world.position_size != world.velocity_size)
    throw std::invalid_argument("the quasi-static stepper takes no 3D rigid body (their rotations are quaternions)");
  unknown_of_.assign(n, -1);
  prescription_of_.assign(n, -1);
  tied_of_.assign(n, -1);
  for (std::size_t p = 0; p < world.prescribed.size(); ++p) {
    const PrescribedComponent& c = world.prescribed[p];
    const int i = world.bodies[c.body].position_offset + c.component;
    if (prescription_of_[i] >= 0)
      throw std::invalid_argument("component " + std::to_string(c.component) + " of body '" +
                                  world.bodies[c.body].name + "' is prescribed twice");
    prescription_of_[i] = static_cast<int>(p);
  }
  for (std::size_t k = 0; k < world.ties.size(); ++k) {
    const RigidTie& tie = world.ties[k];
    const BodyInstance& ring = world.bodies[tie.elastic_body];
    const BodyInstance& hub = world.bodies[tie.rigid_body];
    const auto* fe = dynamic_cast<const FeBody*>(ring.body.get());
    if (!fe || !dynamic_cast<const RigidBody2d*>(hub.body.get()))
      throw std::invalid_argument("tie '" + tie.name + "' must join an elastic body to a plane rigid body");
    const Eigen::Vector2d centre = hub.reference_position.head<2>();
    for (int node : tie.nodes)
      for (int c = 0; c < 2; ++c) {
        const int local = fe->free_index(node, c);
        if (local < 0)
          throw std::invalid_argument("tie '" + tie.name + "': node " + std::to_string(node) + " is fixed");
        const int i = ring.position_offset + local;
        if (tied_of_[i] >= 0 || prescription_of_[i] >= 0)
          throw std::invalid_argument("tie '" + tie.name + "': node " + std::to_string(node) +
                                      " is tied twice or prescribed");
        tied_of_[i] = static_cast<int>(tied_.size());
        tied_.push_back({static_cast<int>(k), c, fe->mesh().nodes[node].head<2>() - centre, hub.position_offset});
      }
  }
  for (int i = 0; i < n; ++i)
    if (prescription_of_[i] < 0 && tied_of_[i] < 0) unknown_of_[i] = unknown_count_++;
  identity_ = unknown_count_ == n;
  for (const RigidTie& tie : world.ties) {
    const int offset = world.bodies[tie.rigid_body].position_offset;
    for (int c = 0; c < 3; ++c)
      if (unknown_of_[offset + c] >= 0 &&
          std::find(hub_unknowns_.begin(), hub_unknowns_.end(), unknown_of_[offset + c]) == hub_unknowns_.end())
        hub_unknowns_.push_back(unknown_of_[offset + c]);
  }
}

void ReducedCoordinates::gather(const Vector& q, Vector& z) const {
  z.resize(unknown_count_);
  for (int i = 0; i < static_cast<int>(unknown_of_.size()); ++i)
    if (unknown_of_[i] >= 0) z(unknown_of_[i]) = q(i);
}

void ReducedCoordinates::expand(const Vector& z, double t, Vector& q) const {
  const int n = static_cast<int>(unknown_of_.size());
  q.resize(n);
  for (int i = 0; i < n; ++i) {
    if (unknown_of_[i] >= 0) {
      q(i) = z(unknown_of_[i]);
    } else if (prescription_of_[i] >= 0) {
      const PrescribedComponent& c = world_.prescribed[prescription_of_[i]];
      const BodyInstance& b = world_.bodies[c.body];
      q(i) = b.reference_position(c.component) + c.value(t);
    }
  }
  // The tied nodes last: their rigid body's coordinates are set by now.
  for (int i = 0; i < n; ++i) {
    if (tied_of_[i] < 0) continue;
    const Tied& tied = tied_[tied_of_[i]];
    const BodyInstance& hub = world_.bodies[world_.ties[tied.tie].rigid_body];
    const Eigen::Vector2d translation = q.segment<2>(tied.rigid_offset) - hub.reference_position.head<2>();
    const double angle = q(tied.rigid_offset + 2) - hub.reference_position(2);
    q(i) = translation(tied.component) + (rotation(angle) * tied.arm - tied.arm)(tied.component);
  }
}

void ReducedCoordinates::tangent(const Vector& q, SparseMatrix& T) const {
  const int n = static_cast<int>(unknown_of_.size());
  Triplets entries;
  entries.reserve(n + 2 * tied_.size());
  for (int i = 0; i < n; ++i) {
    if (unknown_of_[i] >= 0) entries.emplace_back(i, unknown_of_[i], 1.0);
    if (tied_of_[i] < 0) continue;
    const Tied& tied = tied_[tied_of_[i]];
    const BodyInstance& hub = world_.bodies[world_.ties[tied.tie].rigid_body];
    const int x = unknown_of_[tied.rigid_offset + tied.component], phi = unknown_of_[tied.rigid_offset + 2];
    if (x >= 0) entries.emplace_back(i, x, 1.0);
    if (phi >= 0) {
      // ∂(R a)/∂φ = e_z × R a
      const Eigen::Vector2d Ra = rotation(q(tied.rigid_offset + 2) - hub.reference_position(2)) * tied.arm;
      entries.emplace_back(i, phi, tied.component == 0 ? -Ra.y() : Ra.x());
    }
  }
  T.resize(n, unknown_count_);
  T.setFromTriplets(entries.begin(), entries.end());
}

void ReducedCoordinates::reduce_stiffness(const SparseMatrix& K, const SparseMatrix& T, const Vector& q,
                                          const Vector& f, SparseMatrix& K_z) const {
  if (identity_) {
    K_z = K;
    return;
  }
  K_z = SparseMatrix(T.transpose() * K * T);
  // −Σ f_i ∂²u_i/∂φ² = Σ f_i (R a)_i on the hub's angle.
  Triplets geometric;
  for (int i = 0; i < static_cast<int>(tied_of_.size()); ++i) {
    if (tied_of_[i] < 0) continue;
    const Tied& tied = tied_[tied_of_[i]];
    const int phi = unknown_of_[tied.rigid_offset + 2];
    if (phi < 0) continue;
    const BodyInstance& hub = world_.bodies[world_.ties[tied.tie].rigid_body];
    const Eigen::Vector2d Ra = rotation(q(tied.rigid_offset + 2) - hub.reference_position(2)) * tied.arm;
    geometric.emplace_back(phi, phi, f(i) * Ra(tied.component));
  }
  if (!geometric.empty()) {
    SparseMatrix G(unknown_count_, unknown_count_);
    G.setFromTriplets(geometric.begin(), geometric.end());
    K_z += G;
  }
}

}  // namespace csim
