#include "engine/reduced_coordinates.h"

#include "engine/bodies/fe_body.h"
#include "engine/bodies/rigid_body_2d.h"

#include <algorithm>
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

const Eigen::Matrix2d kJ = (Eigen::Matrix2d() << 0.0, -1.0, 1.0, 0.0).finished();  // e_z × in the plane

}  // namespace

ReducedCoordinates::ReducedCoordinates(const World& world, double t) : world_(&world) {
  const int n = world.position_size;
  if (world.position_size != world.velocity_size)
    throw std::invalid_argument("the quasi-static stepper takes no 3D rigid body (their rotations are quaternions)");
  unknown_of_.assign(n, -1);
  prescription_of_.assign(n, -1);
  floating_of_.assign(n, -1);
  for (std::size_t p = 0; p < world.prescribed.size(); ++p) {
    const PrescribedComponent& c = world.prescribed[p];
    if (!c.active(t)) continue;
    const int i = world.bodies[c.body].position_offset + c.component;
    if (prescription_of_[i] >= 0)
      throw std::invalid_argument("component " + std::to_string(c.component) + " of body '" +
                                  world.bodies[c.body].name + "' is prescribed twice");
    prescription_of_[i] = static_cast<int>(p);
  }
  // The unknowns in q's order, a floating node's two at its first component.
  std::vector<bool> tied_node;
  for (std::size_t k = 0; k < world.ties.size(); ++k) {
    const RigidTie& tie = world.ties[k];
    const BodyInstance& ring = world.bodies[tie.elastic_body];
    const BodyInstance& hub = world.bodies[tie.rigid_body];
    const auto* fe = dynamic_cast<const FeBody*>(ring.body.get());
    if (!fe || !dynamic_cast<const RigidBody2d*>(hub.body.get()))
      throw std::invalid_argument("tie '" + tie.name + "' must join an elastic body to a plane rigid body");
    const int nodes = static_cast<int>(fe->mesh().nodes.size());
    if (fe->velocity_size() != 2 * nodes)
      throw std::invalid_argument("tie '" + tie.name + "': a tied body may have no fixed nodes (it rides on its hub)");
    if (floating_of_[ring.position_offset] >= 0)
      throw std::invalid_argument("body '" + ring.name + "' has two ties");
    tied_node.assign(nodes, false);
    for (int node : tie.nodes) tied_node[node] = true;
    for (int node = 0; node < nodes; ++node) {
      Floating f;
      f.rigid_offset = hub.position_offset;
      f.centre_ref = hub.reference_position.head<2>();
      f.angle_ref = hub.reference_position(2);
      f.arm = fe->mesh().nodes[node].head<2>() - f.centre_ref;
      for (int c = 0; c < 2; ++c) {
        f.dof[c] = ring.position_offset + fe->free_index(node, c);
        f.unknown[c] = tied_node[node] ? -1 : -2;  // numbered below
        floating_of_[f.dof[c]] = static_cast<int>(floating_.size());
      }
      floating_.push_back(f);
    }
  }
  for (int i = 0; i < n; ++i) {
    if (prescription_of_[i] >= 0) continue;
    if (floating_of_[i] < 0) {
      unknown_of_[i] = unknown_count_++;
      continue;
    }
    Floating& f = floating_[floating_of_[i]];
    const int c = i == f.dof[0] ? 0 : 1;
    if (f.unknown[c] == -2) f.unknown[c] = unknown_count_++;
  }
  identity_ = unknown_count_ == n && floating_.empty();
  for (const RigidTie& tie : world.ties) {
    const int offset = world.bodies[tie.rigid_body].position_offset;
    for (int c = 0; c < 3; ++c)
      if (unknown_of_[offset + c] >= 0 &&
          std::find(hub_unknowns_.begin(), hub_unknowns_.end(), unknown_of_[offset + c]) == hub_unknowns_.end())
        hub_unknowns_.push_back(unknown_of_[offset + c]);
  }
}

Eigen::Matrix2d ReducedCoordinates::frame(const Floating& node, const Vector& q) const {
  return rotation(q(node.rigid_offset + 2) - node.angle_ref);
}

// x − x_B = R (a + w), with x = X + u = x_B,ref + a + u.
Eigen::Vector2d ReducedCoordinates::current_arm(const Floating& node, const Vector& q) const {
  const Eigen::Vector2d x = node.centre_ref + node.arm + Eigen::Vector2d(q(node.dof[0]), q(node.dof[1]));
  return x - q.segment<2>(node.rigid_offset);
}

void ReducedCoordinates::gather(const Vector& q, Vector& z) const {
  z.resize(unknown_count_);
  for (int i = 0; i < static_cast<int>(unknown_of_.size()); ++i)
    if (unknown_of_[i] >= 0) z(unknown_of_[i]) = q(i);
  for (const Floating& f : floating_) {
    const Eigen::Vector2d w = frame(f, q).transpose() * current_arm(f, q) - f.arm;
    for (int c = 0; c < 2; ++c)
      if (f.unknown[c] >= 0) z(f.unknown[c]) = w(c);
  }
}

void ReducedCoordinates::expand(const Vector& z, double t, Vector& q) const {
  const int n = static_cast<int>(unknown_of_.size());
  q.resize(n);
  for (int i = 0; i < n; ++i) {
    if (unknown_of_[i] >= 0) {
      q(i) = z(unknown_of_[i]);
    } else if (prescription_of_[i] >= 0) {
      const PrescribedComponent& c = world_->prescribed[prescription_of_[i]];
      q(i) = world_->bodies[c.body].reference_position(c.component) + c.value(t);
    }
  }
  // The floating nodes last: their rigid body's coordinates are set by now.
  for (const Floating& f : floating_) {
    Eigen::Vector2d w = Eigen::Vector2d::Zero();
    for (int c = 0; c < 2; ++c)
      if (f.unknown[c] >= 0) w(c) = z(f.unknown[c]);
    const Eigen::Vector2d u = q.segment<2>(f.rigid_offset) + frame(f, q) * (f.arm + w) - f.centre_ref - f.arm;
    q(f.dof[0]) = u(0);
    q(f.dof[1]) = u(1);
  }
}

void ReducedCoordinates::prescribed_forces(const Vector& q, const Vector& f, Vector& forces) const {
  const int n = static_cast<int>(unknown_of_.size());
  forces.setZero(n);
  for (int i = 0; i < n; ++i)
    if (prescription_of_[i] >= 0) forces(i) = f(i);
  for (const Floating& node : floating_) {
    const Eigen::Vector2d force(f(node.dof[0]), f(node.dof[1]));
    for (int c = 0; c < 2; ++c)
      if (prescription_of_[node.rigid_offset + c] >= 0) forces(node.rigid_offset + c) += force(c);
    if (prescription_of_[node.rigid_offset + 2] >= 0)
      forces(node.rigid_offset + 2) += force.dot(kJ * current_arm(node, q));
  }
}

void ReducedCoordinates::tangent(const Vector& q, SparseMatrix& T) const {
  const int n = static_cast<int>(unknown_of_.size());
  Triplets entries;
  entries.reserve(n + 5 * floating_.size());
  for (int i = 0; i < n; ++i)
    if (unknown_of_[i] >= 0) entries.emplace_back(i, unknown_of_[i], 1.0);
  for (const Floating& f : floating_) {
    const Eigen::Matrix2d R = frame(f, q);
    const Eigen::Vector2d turn = kJ * current_arm(f, q);  // ∂x/∂φ
    const int phi = unknown_of_[f.rigid_offset + 2];
    for (int c = 0; c < 2; ++c) {
      const int centre = unknown_of_[f.rigid_offset + c];
      if (centre >= 0) entries.emplace_back(f.dof[c], centre, 1.0);
      if (phi >= 0) entries.emplace_back(f.dof[c], phi, turn(c));
      for (int k = 0; k < 2; ++k)
        if (f.unknown[k] >= 0) entries.emplace_back(f.dof[c], f.unknown[k], R(c, k));
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
  // −Σ f·∂²x: on (φ, φ) f·R(a + w) = f·(x − x_B); on (φ, w_k) and (w_k, φ) −f·(J R e_k).
  Triplets geometric;
  for (const Floating& node : floating_) {
    const int phi = unknown_of_[node.rigid_offset + 2];
    if (phi < 0) continue;
    const Eigen::Matrix2d R = frame(node, q);
    const Eigen::Vector2d force(f(node.dof[0]), f(node.dof[1]));
    geometric.emplace_back(phi, phi, force.dot(current_arm(node, q)));
    const Eigen::Matrix2d JR = kJ * R;
    for (int k = 0; k < 2; ++k) {
      if (node.unknown[k] < 0) continue;
      const double value = -force.dot(JR.col(k));
      geometric.emplace_back(phi, node.unknown[k], value);
      geometric.emplace_back(node.unknown[k], phi, value);
    }
  }
  if (!geometric.empty()) {
    SparseMatrix G(unknown_count_, unknown_count_);
    G.setFromTriplets(geometric.begin(), geometric.end());
    K_z += G;
  }
}

}  // namespace csim
