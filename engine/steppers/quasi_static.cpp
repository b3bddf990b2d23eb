#include "engine/steppers/quasi_static.h"

#include "engine/steppers/contact_solve.h"

#include <sstream>

namespace csim {

QuasiStatic::QuasiStatic(const World& world, const QuasiStaticParameters& parameters)
    : world_(world), parameters_(parameters), forces_(world), detector_(world), pgs_(parameters.solver),
      d_(detector_.dimension()) {
  if (!world.constraints.empty())
    throw RunError(0.0, "the quasi-static stepper does not take linear constraints yet");
  for (const BodyInstance& b : world.bodies)
    if (!b.body->fixed() && !b.body->elastic() && !forces_.has_springs())
      throw RunError(0.0, "quasi-static: body '" + b.name + "' is held by no stiffness (its K would be singular)");
  const int n = world.velocity_size;
  Triplets stiffness;
  for (const BodyInstance& b : world.bodies) b.body->add_stiffness(b.velocity_offset, stiffness);
  forces_.add_spring_stiffness(Vector::Zero(world.position_size), stiffness);
  stiffness_.resize(n, n);
  stiffness_.setFromTriplets(stiffness.begin(), stiffness.end());
  stiffness_factor_.compute(stiffness_);
  if (stiffness_factor_.info() != Eigen::Success || (stiffness_factor_.vectorD().array() <= 0.0).any())
    throw RunError(0.0, "quasi-static: the stiffness is singular (a free body or a rigid-body mode is not held "
                        "by springs or fixed degrees of freedom)");
  double radius = 0.0;
  for (const BodyInstance& b : world.bodies)
    if (!b.body->fixed()) radius = std::max(radius, b.body->bounding_radius);
  contact_distance_ = parameters.contact_distance > 0.0 ? parameters.contact_distance : 0.1 * radius;
}

void QuasiStatic::initialize(State& state) {
  state.energy.elastic = state.energy.initial_elastic = forces_.elastic_energy(state.q);
}

void QuasiStatic::step(State& state) {
  const double h = parameters_.step;
  const double t_next = static_cast<double>(state.counters.steps + 1) * h;
  forces_.external(state.q, t_next, f_);
  u_free_ = stiffness_factor_.solve(f_);

  detector_.detect(state.q, contact_distance_, candidates_, rows_);
  const int nc = static_cast<int>(candidates_.size());
  active_ = candidates_;
  const int m = d_ * nc;
  H_.setZero(m, world_.velocity_size);
  problem_.dimension = d_;
  problem_.contacts = nc;
  problem_.equalities = 0;
  problem_.mu.resize(nc);
  for (int i = 0; i < nc; ++i) {
    for (int k = 0; k < d_; ++k) {
      const SparseRow& row = rows_[d_ * i + k];
      for (int j = 0; j < row.count; ++j) H_(d_ * i + k, row.index[j]) += row.value[j];
    }
    problem_.mu[i] = world_.contact_laws[active_[i].law].mu;
  }
  if (m > 0) {
    X_ = stiffness_factor_.solve(Matrix(H_.transpose()));
    problem_.W.noalias() = H_ * X_;
    problem_.q.noalias() = H_ * (u_free_ - state.q);
    for (int i = 0; i < nc; ++i) problem_.q(d_ * i) += active_[i].point.gap;
  }
  // The warm start and the stored impulses are forces × h (see the header).
  warm_start(state.contacts, active_, d_, m, r_);
  r_ /= h;
  solve_contacts(pgs_, problem_, parameters_.failure_residual, t_next, r_, active_, state.counters);
  u_next_ = u_free_;
  if (m > 0) u_next_.noalias() += X_ * r_;
  if (!u_next_.allFinite()) throw RunError(t_next, "quasi-static: non-finite displacement");
  for (ActiveContact& c : active_) c.impulse *= h;

  state.v = (u_next_ - state.q) / h;
  state.q.swap(u_next_);
  ++state.counters.steps;
  state.t = t_next;
  state.contacts.clear();
  for (const ActiveContact& c : active_)
    if (c.impulse(0) > 0.0) state.contacts.push_back(c);  // open candidates are not contacts
  state.counters.contact_points += static_cast<long>(state.contacts.size());
  state.counters.max_contact_points = std::max(state.counters.max_contact_points, static_cast<int>(state.contacts.size()));
  state.energy.elastic = forces_.elastic_energy(state.q);
}

}  // namespace csim
