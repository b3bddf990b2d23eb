#include "tools/run/probes.h"

#include "tools/scene/scene.h"

namespace csim {

ProbeEvaluator::ProbeEvaluator(const World& world, const RunSettings& run) : world_(world), run_(run) {
  for (const ProbeDefinition& p : run.probes) {
    Eigen::Vector3d reference = Eigen::Vector3d::Zero();
    if (p.body >= 0) {
      const BodyInstance& b = world.bodies[p.body];
      reference = b.body->point_world(b.reference_position, p.point);
    }
    reference_points_.push_back(reference);
  }
}

void ProbeEvaluator::evaluate(const State& state, std::vector<double>& values) const {
  values.resize(run_.probes.size());
  for (std::size_t i = 0; i < run_.probes.size(); ++i) values[i] = evaluate(run_.probes[i], state);
}

double ProbeEvaluator::evaluate(const ProbeDefinition& p, const State& state) const {
  return p.scale * unscaled(p, state);
}

double ProbeEvaluator::unscaled(const ProbeDefinition& p, const State& state) const {
  using Kind = ProbeDefinition::Kind;
  switch (p.kind) {
    case Kind::displacement:
    case Kind::position: {
      const BodyInstance& b = world_.bodies[p.body];
      Eigen::Vector3d x = b.body->point_world(b.positions(state.q), p.point);
      if (p.kind == Kind::displacement) x -= reference_points_[&p - run_.probes.data()];
      return p.direction.dot(x);
    }
    case Kind::velocity:
      return state.v(p.velocity_index);
    case Kind::reaction:
      return state.reactions.size() > 0 ? state.reactions(p.velocity_index) : 0.0;
    case Kind::energy: {
      const EnergyBalance& e = state.energy;
      if (p.energy_term == "kinetic") return e.kinetic;
      if (p.energy_term == "elastic") return e.elastic;
      if (p.energy_term == "mechanical") return e.kinetic + e.elastic;
      if (p.energy_term == "work") return e.work_of_loads;
      if (p.energy_term == "contact_dissipation") return e.contact_dissipation;
      if (p.energy_term == "numerical_dissipation") return e.numerical_dissipation;
      if (p.energy_term == "damping_dissipation") return e.damping_dissipation;
      return e.residual();
    }
    case Kind::contact_force:
      return contact_force(p, state);
    case Kind::contact_count: {
      int count = 0;
      for (const ActiveContact& c : state.contacts) {
        if (c.law != p.contact_law || !(c.impulse(0) > 0.0)) continue;
        if (p.force_component == "closed" || (p.force_component == "stick") == (c.status == ContactStatus::stick))
          ++count;
      }
      return count;
    }
  }
  return 0.0;
}

double ProbeEvaluator::contact_force(const ProbeDefinition& p, const State& state) const {
  const ContactLaw& law = world_.contact_laws[p.contact_law];
  const double h = run_.step;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // on the law's first body
  double normal = 0.0, tangential_2d = 0.0;
  for (const ActiveContact& c : state.contacts) {
    if (c.law != p.contact_law) continue;
    // The impulse acts on the point's body B along +n; the law's first body may be A or B.
    const double sign = c.body_b == law.body_a ? 1.0 : -1.0;
    const Eigen::Vector3d on_b =
        (c.impulse(0) * c.point.normal + c.impulse(1) * c.point.t1 + c.impulse(2) * c.point.t2) / h;
    force += sign * on_b;
    normal += c.impulse(0) / h;
    const Eigen::Vector3d n_into_body = sign * c.point.normal;
    tangential_2d += sign * on_b.dot(Eigen::Vector3d::UnitZ().cross(n_into_body));
  }
  const std::string& k = p.force_component;
  if (k == "normal") return normal;
  if (k == "x") return force.x();
  if (k == "y") return force.y();
  if (k == "z") return force.z();
  if (k == "direction") return force.dot(p.direction);
  if (world_.dimension == 2) return tangential_2d;
  // 3D: magnitude of the resultant's tangential part (about the mean normal).
  Eigen::Vector3d mean_normal = Eigen::Vector3d::Zero();
  for (const ActiveContact& c : state.contacts)
    if (c.law == p.contact_law) mean_normal += c.impulse(0) * c.point.normal;
  if (mean_normal.norm() == 0.0) return 0.0;
  mean_normal.normalize();
  return (force - force.dot(mean_normal) * mean_normal).norm();
}

}  // namespace csim
