#include "engine/dynamics.h"

#include "engine/linear_algebra/same_bits.h"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace csim {

Dynamics::Dynamics(const World& world) : world_(world), springs_(world) {
  for (const Load& load : world.loads) {
    PointJacobian& at_origin = origin_load_jacobians_.emplace_back();
    const BodyInstance& b = world.bodies[load.body];
    if (load.nodal_forces.size() > 0 || !load.point.isZero() || b.body->elastic() || b.body->fixed()) continue;
    const PointJacobian J = b.body->point_jacobian(b.reference_position, load.point);
    for (int k = 0; k < J.count; ++k)
      if (!J.column.col(k).isZero()) at_origin.add(J.index[k], J.column.col(k));
  }
  const int n = world.velocity_size;
  position_of_velocity_.assign(n, -1);
  Triplets mass, damping;
  for (const BodyInstance& b : world.bodies) {
    for (int c = 0; c < b.body->velocity_size(); ++c)
      if (const int coordinate = b.body->coordinate_of(c); coordinate >= 0)
        position_of_velocity_[b.velocity_offset + c] = b.position_offset + coordinate;
    has_elastic_bodies_ = has_elastic_bodies_ || b.body->elastic();
    nonlinear_ = nonlinear_ || b.body->nonlinear();
    has_linear_bodies_ = has_linear_bodies_ || (b.body->elastic() && !b.body->nonlinear());
    gyroscopic_ = gyroscopic_ || b.body->has_inertial_force();
    b.body->add_mass(b.velocity_offset, mass);
    b.body->add_damping(b.velocity_offset, damping);
  }
  mass_.resize(n, n);
  mass_.setFromTriplets(mass.begin(), mass.end());
  damping_.resize(n, n);
  damping_.setFromTriplets(damping.begin(), damping.end());
  if (!world.gravity.isZero()) {
    weight_.setZero(n);
    for (const BodyInstance& b : world.bodies)
      if (!b.body->fixed())
        b.body->add_weight(b.reference_position, world.gravity, weight_.segment(b.velocity_offset, b.body->velocity_size()));
  }
}

SparseMatrix Dynamics::body_stiffness() const {
  Triplets stiffness;
  for (const BodyInstance& b : world_.bodies) b.body->add_stiffness(b.velocity_offset, stiffness);
  SparseMatrix K(size(), size());
  K.setFromTriplets(stiffness.begin(), stiffness.end());
  return K;
}

void Dynamics::force(double t, const Vector& q, const Vector& v, Vector& f, Vector* loads, Vector* damping) const {
  external(q, t, f);
  add_inertial_forces(v, f);
  if (loads) *loads = f;
  add_internal_forces(q, f);
  if (!damping) {
    add_damping_force(v, f);
    return;
  }
  damping->setZero(size());
  add_damping_force(v, *damping);
  f += *damping;
}

void Dynamics::add_inertial_forces(const Vector& v, Vector& f) const {
  if (!gyroscopic_) return;
  for (const BodyInstance& b : world_.bodies)
    if (b.body->has_inertial_force())
      b.body->add_inertial_force(v.segment(b.velocity_offset, b.body->velocity_size()),
                                 f.segment(b.velocity_offset, b.body->velocity_size()));
}

void Dynamics::add_internal_forces(const Vector& q, Vector& f) const {
  add_spring_forces(q, f);
  add_body_internal_forces(q, f);
}

void Dynamics::add_damping_force(const Vector& v, Vector& f) const {
  if (has_damping()) f.noalias() -= damping_ * v;
}

std::size_t Dynamics::add_internal_forces_and_tangent(const Vector& q, Vector& f, Triplets* stiffness,
                                                      const BodyFrames* frames) const {
  add_spring_forces(q, f);
  Vector frame_positions, frame_force;
  auto in_frame = [&](int i) { return frames && frames->in_frame(i) && world_.bodies[i].body->nonlinear(); };
  for (int i = 0; i < static_cast<int>(world_.bodies.size()); ++i) {
    const BodyInstance& b = world_.bodies[i];
    if (!in_frame(i)) continue;
    frames->frame_positions(q, i, frame_positions);
    frame_force.setZero(b.body->velocity_size());
    if (stiffness) b.body->add_internal_force_and_tangent(frame_positions, frame_force, b.velocity_offset, *stiffness);
    else b.body->add_internal_force(frame_positions, frame_force);
    frames->add_turned_to_world(q, i, frame_force, f.segment(b.velocity_offset, b.body->velocity_size()));
  }
  const std::size_t world_from = stiffness ? stiffness->size() : 0;
  for (int i = 0; i < static_cast<int>(world_.bodies.size()); ++i) {
    const BodyInstance& b = world_.bodies[i];
    if (!b.body->elastic() || in_frame(i)) continue;
    VectorRef slice = f.segment(b.velocity_offset, b.body->velocity_size());
    if (stiffness) b.body->add_internal_force_and_tangent(b.positions(q), slice, b.velocity_offset, *stiffness);
    else b.body->add_internal_force(b.positions(q), slice);
  }
  if (stiffness) add_spring_stiffness(q, *stiffness);
  return world_from;
}

void Dynamics::add_stiffness(const Vector& q, Triplets& K) const {
  add_body_stiffness(q, K);
  add_spring_stiffness(q, K);
}

void Dynamics::add_body_stiffness(const Vector& q, Triplets& K) const {
  for (const BodyInstance& b : world_.bodies)
    if (b.body->elastic()) b.body->add_tangent_stiffness(b.positions(q), b.velocity_offset, K);
}

// Central differences of each rotating body's gyroscopic force, on its own velocity components.
void Dynamics::add_inertial_tangent(const Vector& v, Triplets& D) const {
  if (!gyroscopic_) return;
  for (const BodyInstance& b : world_.bodies) {
    if (!b.body->has_inertial_force()) continue;
    const int m = b.body->velocity_size();
    Vector slice = v.segment(b.velocity_offset, m), plus(m), minus(m);
    for (int j = 0; j < m; ++j) {
      const double delta = 1e-6 * std::max(1.0, slice.cwiseAbs().maxCoeff());
      const double kept = slice(j);
      plus.setZero();
      minus.setZero();
      slice(j) = kept + delta;
      b.body->add_inertial_force(slice, plus);
      slice(j) = kept - delta;
      b.body->add_inertial_force(slice, minus);
      slice(j) = kept;
      for (int i = 0; i < m; ++i) {
        const double value = -(plus(i) - minus(i)) / (2.0 * delta);
        if (value != 0.0) D.emplace_back(b.velocity_offset + i, b.velocity_offset + j, value);
      }
    }
  }
}

void Dynamics::equality_rows(double t, EqualityRows& equalities) const {
  const int n = world_.velocity_size;
  equalities.prescriptions.clear();
  for (int p = 0; p < static_cast<int>(world_.prescribed.size()); ++p)
    if (world_.prescribed[p].active(t)) equalities.prescriptions.push_back(p);
  const int nw = static_cast<int>(world_.constraints.size());
  const int ne = nw + static_cast<int>(equalities.prescriptions.size());
  equalities.rows.setZero(ne, n);
  equalities.terms.assign(ne, {});
  for (int e = 0; e < nw; ++e)
    for (const auto& [index, coefficient] : world_.constraints[e].terms) {
      equalities.rows(e, index) += coefficient;
      equalities.terms[e].emplace_back(position_of_velocity_[index], coefficient);
    }
  for (int i = 0; i < static_cast<int>(equalities.prescriptions.size()); ++i) {
    const PrescribedComponent& c = world_.prescribed[equalities.prescriptions[i]];
    const int index = world_.bodies[c.body].velocity_offset + c.component;
    equalities.rows(nw + i, index) = 1.0;
    equalities.terms[nw + i].emplace_back(position_of_velocity_[index], 1.0);
  }
}

double Dynamics::kinetic_energy(const Vector& v) const {
  work_.noalias() = mass_ * v;
  return 0.5 * v.dot(work_);
}

double Dynamics::kinetic_energy(const Vector& v, const Vector& x, Vector& Mx) const {
  // Eigen's column-major sparse × dense product, written out for two right-hand sides: each result
  // entry takes the same terms in the same order (column by column), hence the same bits.
  work_.setZero(size());
  Mx.setZero(size());
  for (int j = 0; j < mass_.outerSize(); ++j) {
    const double vj = v(j), xj = x(j);
    for (SparseMatrix::InnerIterator it(mass_, j); it; ++it) {
      work_(it.index()) += it.value() * vj;
      Mx(it.index()) += it.value() * xj;
    }
  }
  return 0.5 * v.dot(work_);
}

const Vector& Dynamics::linear_body_products(const Vector& q) const {
  if (kept_positions_.size() == q.size() &&
      same_bits(q.data(), kept_positions_.data(), q.size()))
    return kept_products_;
  kept_products_.resize(size());
  for (const BodyInstance& b : world_.bodies)
    if (b.body->elastic() && !b.body->nonlinear())
      b.body->stiffness_product(b.positions(q), kept_products_.segment(b.velocity_offset, b.body->velocity_size()));
  kept_positions_ = q;
  return kept_products_;
}

const LinearProducts& Dynamics::linear_product_table() const {
  if (nonlinear_) throw std::logic_error("Dynamics: the linear products of a World with a nonlinear body");
  if (linear_products_.size() != size()) {
    std::vector<LinearProducts::StiffnessBlock> blocks;
    for (const BodyInstance& b : world_.bodies)
      if (const SparseMatrix* K = b.body->linear_stiffness()) blocks.push_back({b.velocity_offset, b.position_offset, K});
    linear_products_ = LinearProducts(std::move(blocks), mass_);
  }
  return linear_products_;
}

void Dynamics::linear_products(const Vector& q, const Vector& v, const Vector* dv, Vector& Kv, Vector& Mv,
                               Vector* Mdv) const {
  linear_product_table().multiply(q, v, dv, kept_products_, Kv, Mv, Mdv);
  kept_positions_ = q;
  springs_.add_stiffness_product(q, v, Kv);
}

void Dynamics::apply_linear_stiffness(const Vector& q, const Vector& v, Vector& Kv) const {
  linear_product_table().multiply_stiffness(v, Kv);
  springs_.add_stiffness_product(q, v, Kv);
}

void Dynamics::add_body_internal_forces(const Vector& q, Vector& f) const {
  const Vector* products = has_linear_bodies_ ? &linear_body_products(q) : nullptr;
  for (const BodyInstance& b : world_.bodies) {
    if (!b.body->elastic()) continue;
    auto force = f.segment(b.velocity_offset, b.body->velocity_size());
    if (b.body->nonlinear()) b.body->add_internal_force(b.positions(q), force);
    else force -= products->segment(b.velocity_offset, b.body->velocity_size());
  }
}

namespace {

// Loads and gravity at each of N times, the loads' points taken at q once (their Jacobians do not depend
// on t): forces[i] at times[i], each the same to the bit as a call at that time alone. weight: the
// bodies' weight, formed once (0 + w is w to the bit, as add_weight's sum into zeros).
template <std::size_t N>
void external_forces(const World& world, const Vector& weight, const std::vector<PointJacobian>& origin_jacobians,
                     const Vector& q, const std::array<double, N>& times, const std::array<Vector*, N>& forces) {
  Vector& first = *forces[0];
  first.setZero(world.velocity_size);
  if (weight.size() > 0) first += weight;
  for (std::size_t i = 1; i < N; ++i) *forces[i] = first;
  PointJacobian turning;
  for (std::size_t l = 0; l < world.loads.size(); ++l) {
    const Load& load = world.loads[l];
    const BodyInstance& b = world.bodies[load.body];
    if (load.nodal_forces.size() > 0) {  // a distributed load, already in the body's coordinates
      for (std::size_t i = 0; i < N; ++i)
        forces[i]->segment(b.velocity_offset, b.body->velocity_size()) += load.multiplier(times[i]) * load.nodal_forces;
      continue;
    }
    const PointJacobian& at_origin = origin_jacobians[l];
    if (at_origin.count == 0) turning = b.body->point_jacobian(b.positions(q), load.point);
    const PointJacobian& J = at_origin.count > 0 ? at_origin : turning;
    for (std::size_t i = 0; i < N; ++i) {
      const double multiplier = load.multiplier(times[i]);
      for (int k = 0; k < J.count; ++k)
        (*forces[i])(b.velocity_offset + J.index[k]) += J.column.col(k).dot(multiplier * load.force);
    }
  }
}

}  // namespace

void Dynamics::external(const Vector& q, double t, Vector& f) const {
  external_forces<1>(world_, weight_, origin_load_jacobians_, q, {t}, {&f});
}

void Dynamics::external(const Vector& q, double t_a, double t_b, Vector& f_a, Vector& f_b) const {
  external_forces<2>(world_, weight_, origin_load_jacobians_, q, {t_a, t_b}, {&f_a, &f_b});
}

double Dynamics::elastic_energy(const Vector& q) const {
  double energy = 0.0;
  const Vector* products = has_linear_bodies_ ? &linear_body_products(q) : nullptr;
  for (const BodyInstance& b : world_.bodies) {
    if (!b.body->elastic()) continue;
    if (b.body->nonlinear()) energy += b.body->strain_energy(b.positions(q));
    else energy += 0.5 * b.positions(q).dot(products->segment(b.velocity_offset, b.body->velocity_size()));
  }
  springs_.add_energy(q, energy);
  return energy;
}

}  // namespace csim
