#include "engine/steppers/generalized_alpha.h"


#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace csim {

namespace {

constexpr double kActivationFraction = 0.5;  // a contact is active when its gap closes over this part of the free step
constexpr int kTimerSampling = 16;

MassSolver make_mass_solver(const Dynamics& dynamics) {
  try {
    return MassSolver(dynamics);
  } catch (const std::invalid_argument& e) {
    throw RunError(0.0, std::string("generalized-alpha: ") + e.what());
  }
}

}  // namespace

std::string GeneralizedAlpha::unsupported(const World& world) {
  const std::string instead = "; use moreau-jean";
  for (const BodyInstance& b : world.bodies) {
    if (b.body->fixed()) continue;
    if (b.body->position_size() != b.body->velocity_size())
      return "generalized-alpha does not integrate the rotations of 3D rigid bodies (body '" + b.name + "')" + instead;
    if (b.body->nonlinear())
      return "generalized-alpha does not take finite-strain bodies (body '" + b.name + "': its step needs Newton's loop)" +
             instead;
  }
  if (!world.constraints.empty()) return "generalized-alpha does not take linear constraints ('constraints')" + instead;
  if (!world.prescribed.empty()) return "generalized-alpha does not take prescribed motions ('prescribed')" + instead;
  if (!world.ties.empty()) return "generalized-alpha does not take ties ('tie')" + instead;
  // Rayleigh damping of one body shares the modes of M and K (header); of two, or with springs, not.
  int damped = 0;
  for (const BodyInstance& b : world.bodies) {
    Triplets damping;
    b.body->add_damping(0, damping);
    damped += damping.empty() ? 0 : 1;
  }
  if (damped > 1 || (damped == 1 && !world.springs.empty()))
    return "generalized-alpha takes Rayleigh damping on a single body without springs (other damping makes its "
           "Delassus operator nonsymmetric)" + instead;
  return "";
}

GeneralizedAlpha::GeneralizedAlpha(const World& world, const GeneralizedAlphaParameters& parameters)
    : world_(world),
      parameters_(parameters),
      coefficients_(parameters.rho_infinity),
      dynamics_(world),
      operators_(dynamics_),
      mass_(make_mass_solver(dynamics_)),
      stage_(world, parameters.solver, make_response()) {
  if (const std::string refusal = unsupported(world); !refusal.empty()) throw RunError(0.0, refusal);
  if (!(parameters.rho_infinity >= 0.0 && parameters.rho_infinity <= 1.0))
    throw RunError(0.0, "generalized-alpha: rho_infinity must lie in [0, 1]");
  stage_.set_delassus_choice(parameters.delassus_storage);
}

// The stage's view of the step's contact response (generalized_alpha_response.h), which update() also
// drives (the jumps of q and ẅ).
std::unique_ptr<IterationOperator> GeneralizedAlpha::make_response() {
  auto response = std::make_unique<GeneralizedAlphaResponse>(operators_, mass_, coefficients_, parameters_.step);
  response_ = response.get();
  return response;
}

void GeneralizedAlpha::summarize_settings(SummaryEntries& out) const {
  out.add("rho_infinity", parameters_.rho_infinity)
      .add("alpha_m", coefficients_.alpha_m)
      .add("alpha_f", coefficients_.alpha_f)
      .add("gamma", coefficients_.gamma)
      .add("beta", coefficients_.beta);
}

// ẅ_0 = M⁻¹ f(0, q_0, v_0), contacts left out, and a_0 = ẅ_0.
void GeneralizedAlpha::initialize(State& state) {
  state.energy.kinetic = state.energy.initial_kinetic = dynamics_.kinetic_energy(state.v);
  state.energy.elastic = state.energy.initial_elastic = dynamics_.elastic_energy(state.q);
  dynamics_.force(state.t, state.q, state.v, acceleration_);
  mass_.solve_in_place(acceleration_);
  recursion_ = acceleration_;
}

// The step without contacts (header): v_free, q_free, ẅ_free.
void GeneralizedAlpha::free_step(const State& state) {
  const double h = parameters_.step;
  const GeneralizedAlphaCoefficients& k = coefficients_;
  const double cw = k.acceleration_weight();
  operators_.update_coefficients(state.q, h * k.gamma * cw, h * h * k.beta * cw);
  a_star_ = (k.alpha_f * acceleration_ - k.alpha_m * recursion_) / (1.0 - k.alpha_m);
  v_hat_ = state.v + (h * (1.0 - k.gamma)) * recursion_ + (h * k.gamma) * a_star_;
  q_hat_ = state.q + h * state.v + (h * h * (0.5 - k.beta)) * recursion_ + (h * h * k.beta) * a_star_;
  // For the work of loads (no gyroscopic body here).
  dynamics_.external(state.q, state.t, state.t + h, f_loads_start_, f_loads_end_);
  f_total_ = f_loads_end_;
  dynamics_.add_internal_forces(state.q, f_total_);
  if (operators_.has_stiffness()) {
    work_ = q_hat_ - state.q;
    operators_.apply_stiffness(work_, work2_);
    f_total_ -= work2_;
  }
  dynamics_.add_damping_force(v_hat_, f_total_);
  w_free_ = f_total_;
  operators_.solve_in_place(w_free_);
  v_free_ = v_hat_ + (h * k.gamma * cw) * w_free_;
  q_free_ = q_hat_ + (h * h * k.beta * cw) * w_free_;
  if (!v_free_.allFinite() || !q_free_.allFinite()) {
    std::ostringstream message;
    message << "non-finite free velocity at t = " << state.t + h
            << " s (forces or stiffness overflow: check the loads, masses and the time step)";
    throw RunError(state.t + h, message.str());
  }
}

void GeneralizedAlpha::detect(const State& state) {
  const double h = parameters_.step;
  work_ = (q_free_ - state.q) / h;  // the free step's mean velocity
  double margin = 0.0;
  if (!stage_.empty()) {
    const ContactDetector& detector = stage_.detector();
    margin = 2.0 * std::max({detector.travel_bound(state.v, h), detector.travel_bound(v_free_, h),
                             detector.travel_bound(work_, h)}) + 1e-12;
  }
  stage_.detect(state.q, margin);
  for (int k = 0; k < stage_.candidate_count(); ++k)
    if (stage_.predicted_gap(k, work_, kActivationFraction * h) <= stage_.touching()) stage_.activate(k);
}

// The contact stage's rows, W (generalized_alpha_response.h) and b = H v_free, with Newton's impact
// law and the closing of open gaps.
void GeneralizedAlpha::assemble(const State& state) {
  const int d = stage_.dimension();
  const double h = parameters_.step;
  stage_.gather_rows(nullptr, nullptr, state.t + h);
  stage_.form_delassus();
  stage_.free_term(v_free_);
  Vector& b = stage_.problem().b;
  const std::vector<ActiveContact>& active = stage_.active();
  work_ = q_free_ - state.q;  // the free step's displacement, for the open gaps below
  for (int i = 0; i < static_cast<int>(active.size()); ++i) {
    const double e = world_.contact_laws[active[i].law].restitution;
    const SparseRow& normal = *stage_.rows().contact[d * i];
    if (e > 0.0) {
      b(d * i) += e * normal.dot(state.v);
      continue;
    }
    // An inelastic contact still open by g closes it within the step: g(q_{n+1}) ≥ 0 with
    // q_{n+1} − q_free ≈ ½ h (v_{n+1} − v_free) along its normal (header).
    const double opening = active[i].point.gap + normal.dot(work_) - 0.5 * h * normal.dot(v_free_);
    if (opening > 0.0) b(d * i) += opening / (0.5 * h);
  }
}

void GeneralizedAlpha::update() {
  v_next_ = v_free_;
  q_next_ = q_free_;
  w_next_ = w_free_;
  response_->add_jumps(stage_.impulses(), v_next_, q_next_, w_next_);
  const GeneralizedAlphaCoefficients& k = coefficients_;
  a_next_ = k.acceleration_weight() * w_next_ + a_star_;
}

void GeneralizedAlpha::account_energy(State& state) {
  const double h = parameters_.step;
  EnergyBalance& e = state.energy;
  work_ = q_next_ - state.q;  // Δq
  e.work_of_loads += 0.5 * (f_loads_start_ + f_loads_end_).dot(work_);
  const Vector& r = stage_.impulses();
  for (int a = 0; a < r.size(); ++a) e.contact_dissipation -= r(a) * stage_.rows().dot(a, work_) / h;
  if (operators_.has_damping()) {
    work2_ = 0.5 * (state.v + v_next_);
    operators_.apply_damping(work2_, v_hat_);  // v̂ is spent: a work vector here
    e.damping_dissipation += work_.dot(v_hat_);
  }
  e.kinetic = dynamics_.kinetic_energy(v_next_);
  e.elastic = dynamics_.elastic_energy(q_next_);
  // No closed discrete balance (header): the numerical term is what closes it.
  e.numerical_dissipation = 0.0;
  e.numerical_dissipation = -e.residual();
}

void GeneralizedAlpha::step(State& state) {
  clock_.start(state.counters.steps % kTimerSampling == kTimerSampling - 1, kTimerSampling);
  free_step(state);
  clock_.lap(state.timers.free_velocity);
  detect(state);
  clock_.lap(state.timers.detection);
  assemble(state);
  clock_.lap(state.timers.assembly);
  stage_.solve(state.contacts, true, parameters_.failure_residual, state.t + parameters_.step, state.counters);
  clock_.lap(state.timers.solve);
  update();
  account_energy(state);
  const double t_next = state.t + parameters_.step;
  if (!v_next_.allFinite() || !q_next_.allFinite()) {
    std::ostringstream message;
    message << "non-finite state at t = " << t_next << " s (check the time step, stiffness and loads)";
    throw RunError(t_next, message.str());
  }
  state.q.swap(q_next_);
  state.v.swap(v_next_);
  acceleration_.swap(w_next_);
  recursion_.swap(a_next_);
  SolverCounters& counters = state.counters;
  ++counters.steps;
  state.t = static_cast<double>(counters.steps) * parameters_.step;
  stage_.hand_over(state.contacts);
  counters.count_contacts(state.contacts);
  state.factorization_seconds = operators_.factorization_seconds();
  clock_.lap(state.timers.update);
}

}  // namespace csim
