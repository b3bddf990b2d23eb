#include "engine/steppers/generalized_alpha.h"

#include "engine/contact_stage/contact_solve.h"

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
      pgs_(parameters.solver),
      detector_(world),
      contact_dimension_(detector_.dimension()) {
  if (const std::string refusal = unsupported(world); !refusal.empty()) throw RunError(0.0, refusal);
  if (!(parameters.rho_infinity >= 0.0 && parameters.rho_infinity <= 1.0))
    throw RunError(0.0, "generalized-alpha: rho_infinity must lie in [0, 1]");
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
  active_.clear();
  active_rows_.clear();
  if (detector_.empty()) return;
  const double h = parameters_.step;
  work_ = (q_free_ - state.q) / h;  // the free step's mean velocity
  const double reach = std::max({detector_.travel_bound(state.v, h), detector_.travel_bound(v_free_, h),
                                 detector_.travel_bound(work_, h)});
  detector_.detect(state.q, 2.0 * reach + 1e-12, candidates_, candidate_rows_);
  for (std::size_t i = 0; i < candidates_.size(); ++i) {
    const double closing = candidate_rows_[contact_dimension_ * i].dot(work_);
    if (candidates_[i].point.gap + kActivationFraction * h * closing > 0.0) continue;
    active_.push_back(candidates_[i]);
    active_rows_.push_back(static_cast<int>(i));
  }
}

// Z = M⁻¹ hᵀ and G = S⁻¹ (hᵀ + c K Z) of the row, kept while S and the row stay.
const GeneralizedAlpha::RowColumns& GeneralizedAlpha::columns(const RowKey& key, const SparseRow& row) {
  RowColumns& col = columns_[key];
  col.used = true;
  if (col.factorization == operators_.factorizations() && col.row == row) return col;
  const int n = world_.velocity_size;
  const double h = parameters_.step;
  const GeneralizedAlphaCoefficients& k = coefficients_;
  const double c = h * h * k.acceleration_weight() * (k.beta - 0.5 * k.gamma);
  col.row = row;
  col.factorization = operators_.factorizations();
  col.Z.setZero(n);
  row.scatter(1.0, col.Z);
  col.G = col.Z;
  mass_.solve_in_place(col.Z);
  if (operators_.has_stiffness() && c > 0.0) {
    operators_.apply_stiffness(col.Z, work2_);
    col.G += c * work2_;
  }
  operators_.solve_in_place(col.G);
  return col;
}

void GeneralizedAlpha::assemble(const State& state) {
  const int d = contact_dimension_;
  const int nc = static_cast<int>(active_.size());
  const int m = d * nc;
  const double h = parameters_.step;

  problem_.dimension = d;
  problem_.contacts = nc;
  problem_.equalities = 0;
  problem_.mu.resize(nc);
  rows_.resize(m);
  row_columns_.resize(m);
  for (auto& entry : columns_) entry.second.used = false;
  for (int i = 0; i < nc; ++i) {
    problem_.mu[i] = world_.contact_laws[active_[i].law].mu_at(state.t + h);
    for (int r = 0; r < d; ++r) {
      rows_[d * i + r] = candidate_rows_[d * active_rows_[i] + r];
      row_columns_[d * i + r] = &columns({active_[i].point.key, r}, rows_[d * i + r]);
    }
  }
  std::erase_if(columns_, [](const auto& entry) { return !entry.second.used; });
  problem_.W.resize(m, m);
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) problem_.W(a, b) = rows_[a].dot(row_columns_[b]->G);
  // Symmetric in exact arithmetic (header); its two triangles differ by the solves' round-off.
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < a; ++b) problem_.W(a, b) = problem_.W(b, a) = 0.5 * (problem_.W(a, b) + problem_.W(b, a));
  problem_.b.resize(m);
  for (int a = 0; a < m; ++a) problem_.b(a) = rows_[a].dot(v_free_);
  work_ = q_free_ - state.q;  // the free step's displacement, for the open gaps below
  for (int i = 0; i < nc; ++i) {
    const double e = world_.contact_laws[active_[i].law].restitution;
    const SparseRow& normal = rows_[d * i];
    if (e > 0.0) {
      problem_.b(d * i) += e * normal.dot(state.v);
      continue;
    }
    // An inelastic contact still open by g closes it within the step: g(q_{n+1}) ≥ 0 with
    // q_{n+1} − q_free ≈ ½ h (v_{n+1} − v_free) along its normal (header).
    const double opening = active_[i].point.gap + normal.dot(work_) - 0.5 * h * normal.dot(v_free_);
    if (opening > 0.0) problem_.b(d * i) += opening / (0.5 * h);
  }
}

// A jump of impulse R along hᵀ (out of the recursion): v += R G, q += R [(hβ/γ) G + h(½ − β/γ) Z],
// ẅ += R (G − Z)/(hγc_w).
void GeneralizedAlpha::add_jump(const RowColumns& col, double impulse, Vector& v, Vector& q, Vector& w) const {
  const double h = parameters_.step;
  const GeneralizedAlphaCoefficients& k = coefficients_;
  const double cw = k.acceleration_weight();
  v += impulse * col.G;
  q += (impulse * h * k.beta / k.gamma) * col.G + (impulse * h * (0.5 - k.beta / k.gamma)) * col.Z;
  w += (impulse / (h * k.gamma * cw)) * (col.G - col.Z);
}

void GeneralizedAlpha::solve(State& state) {
  warm_start(state.contacts, active_, contact_dimension_, problem_.size(), r_);
  const double t_next = state.t + parameters_.step;
  if (const std::string failure =
          solve_contacts(pgs_, problem_, parameters_.failure_residual, t_next, r_, active_, state.counters, &statuses_);
      !failure.empty())
    throw RunError(t_next, failure);
}

void GeneralizedAlpha::update() {
  v_next_ = v_free_;
  q_next_ = q_free_;
  w_next_ = w_free_;
  for (int a = 0; a < static_cast<int>(rows_.size()); ++a)
    if (r_(a) != 0.0) add_jump(*row_columns_[a], r_(a), v_next_, q_next_, w_next_);
  const GeneralizedAlphaCoefficients& k = coefficients_;
  a_next_ = k.acceleration_weight() * w_next_ + a_star_;
}

void GeneralizedAlpha::account_energy(State& state) {
  const double h = parameters_.step;
  EnergyBalance& e = state.energy;
  work_ = q_next_ - state.q;  // Δq
  e.work_of_loads += 0.5 * (f_loads_start_ + f_loads_end_).dot(work_);
  for (int a = 0; a < static_cast<int>(rows_.size()); ++a) e.contact_dissipation -= r_(a) * rows_[a].dot(work_) / h;
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
  solve(state);
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
  state.contacts.swap(active_);
  counters.contact_points += static_cast<long>(state.contacts.size());
  counters.max_contact_points = std::max(counters.max_contact_points, static_cast<int>(state.contacts.size()));
  state.factorization_seconds = operators_.factorization_seconds();
  clock_.lap(state.timers.update);
}

}  // namespace csim
