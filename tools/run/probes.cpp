#include "tools/run/probes.h"

#include "engine/bodies/fe_body.h"
#include "tools/scene/scene.h"

namespace csim {

ProbeEvaluator::ProbeEvaluator(const World& world, const RunSettings& run) : world_(world), run_(run) {
  for (const ProbeDefinition& p : run.probes) {
    Eigen::Vector3d reference = Eigen::Vector3d::Zero();
    std::optional<MeshPoint> element_point;
    const bool at_point = p.kind == ProbeDefinition::Kind::displacement || p.kind == ProbeDefinition::Kind::position;
    if (p.body >= 0) {
      const BodyInstance& b = world.bodies[p.body];
      reference = b.body->point_world(b.reference_position, p.point);
      // FeBody::point_world locates such a point at every call; a probe is read at every step.
      if (const FeBody* fe = b.body->finite_elements(); fe && at_point && fe->node_at(p.point) < 0)
        element_point = fe->locate(p.point);
    }
    reference_points_.push_back(reference);
    element_points_.push_back(element_point);
    static const std::pair<const char*, Term> term_names[] = {
        {"kinetic", Term::kinetic}, {"elastic", Term::elastic}, {"mechanical", Term::mechanical},
        {"work", Term::work}, {"contact_dissipation", Term::contact_dissipation},
        {"numerical_dissipation", Term::numerical_dissipation}, {"damping_dissipation", Term::damping_dissipation},
        {"sleep_dissipation", Term::sleep_dissipation}};
    Term term = Term::balance;
    for (const auto& [name, t] : term_names)
      if (p.energy_term == name) term = t;
    terms_.push_back(term);
    static const std::pair<const char*, Component> component_names[] = {
        {"normal", Component::normal}, {"x", Component::x}, {"y", Component::y}, {"z", Component::z},
        {"direction", Component::direction}, {"closed", Component::closed}, {"stick", Component::stick},
        {"slip", Component::slip}};
    Component component = Component::tangential;
    for (const auto& [name, c] : component_names)
      if (p.force_component == name) component = c;
    components_.push_back(component);
  }
}

void ProbeEvaluator::evaluate(const State& state, std::vector<double>& values) const {
  values.resize(run_.probes.size());
  for (std::size_t i = 0; i < run_.probes.size(); ++i) values[i] = run_.probes[i].scale * unscaled(i, state);
}

void ProbeEvaluator::evaluate(const State& state, std::vector<double>& values, const std::vector<int>& only) const {
  values.resize(run_.probes.size());
  for (const int i : only) values[i] = run_.probes[i].scale * unscaled(i, state);
}

bool ProbeEvaluator::reads_energy() const {
  for (const ProbeDefinition& p : run_.probes)
    if (p.kind == ProbeDefinition::Kind::energy) return true;
  return false;
}

double ProbeEvaluator::unscaled(std::size_t i, const State& state) const {
  using Kind = ProbeDefinition::Kind;
  const ProbeDefinition& p = run_.probes[i];
  switch (p.kind) {
    case Kind::displacement:
    case Kind::position: {
      const BodyInstance& b = world_.bodies[p.body];
      const std::optional<MeshPoint>& element_point = element_points_[i];
      Eigen::Vector3d x = element_point ? Eigen::Vector3d(p.point + b.body->finite_elements()->displacement_at(
                                                               b.positions(state.q), *element_point))
                                        : b.body->point_world(b.positions(state.q), p.point);
      if (p.kind == Kind::displacement) x -= reference_points_[i];
      return p.direction.dot(x);
    }
    case Kind::velocity:
      return state.v(p.velocity_index);
    case Kind::reaction:
      return state.reactions.size() > 0 ? state.reactions(p.velocity_index) : 0.0;
    case Kind::energy: {
      const EnergyBalance& e = state.energy;
      switch (terms_[i]) {
        case Term::kinetic: return e.kinetic;
        case Term::elastic: return e.elastic;
        case Term::mechanical: return e.kinetic + e.elastic;
        case Term::work: return e.work_of_loads;
        case Term::contact_dissipation: return e.contact_dissipation;
        case Term::numerical_dissipation: return e.numerical_dissipation;
        case Term::damping_dissipation: return e.damping_dissipation;
        case Term::sleep_dissipation: return e.sleep_dissipation;
        case Term::balance: return e.residual();
      }
      return e.residual();
    }
    case Kind::contact_force:
      return contact_force(i, state);
    case Kind::contact_count: {
      int count = 0;
      for (const ActiveContact& c : state.contacts) {
        if (c.law != p.contact_law || !(c.impulse(0) > 0.0)) continue;
        if (components_[i] == Component::closed || (components_[i] == Component::stick) == (c.status == ContactStatus::stick))
          ++count;
      }
      return count;
    }
  }
  return 0.0;
}

double ProbeEvaluator::contact_force(std::size_t i, const State& state) const {
  const ProbeDefinition& p = run_.probes[i];
  const ContactLaw& law = world_.contact_laws[p.contact_law];
  const double h = run_.step;
  const Component k = components_[i];
  if (k == Component::normal) {  // the sum below, alone
    double normal = 0.0;
    for (const ActiveContact& c : state.contacts)
      if (c.law == p.contact_law) normal += c.impulse(0) / h;
    return normal;
  }
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // on the law's first body
  double tangential_2d = 0.0;
  for (const ActiveContact& c : state.contacts) {
    if (c.law != p.contact_law) continue;
    // The impulse acts on the point's body B along +n; the law's first body may be A or B.
    const double sign = c.body_b == law.body_a ? 1.0 : -1.0;
    const Eigen::Vector3d on_b =
        (c.impulse(0) * c.point.normal + c.impulse(1) * c.point.t1 + c.impulse(2) * c.point.t2) / h;
    force += sign * on_b;
    const Eigen::Vector3d n_into_body = sign * c.point.normal;
    tangential_2d += sign * on_b.dot(Eigen::Vector3d::UnitZ().cross(n_into_body));
  }
  if (k == Component::x) return force.x();
  if (k == Component::y) return force.y();
  if (k == Component::z) return force.z();
  if (k == Component::direction) return force.dot(p.direction);
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
