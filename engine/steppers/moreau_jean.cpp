#include "engine/steppers/moreau_jean.h"

#include "engine/contact_stage/body_block_operator.h"
#include "engine/linear_algebra/same_bits.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace csim {

namespace {

// Two halves (moreau_jean.h): the margin's travel, as a multiple of the faster of v_k and the last v_θ.
// A step's motion seldom doubles (a start from rest, a velocity through zero): those steps are taken
// again.
constexpr double kReachGrowth = 2.0;

constexpr int kTimerSampling = 16;

}  // namespace

MoreauJean::MoreauJean(const World& world, const MoreauJeanParameters& parameters)
    : world_(world),
      parameters_(parameters),
      dynamics_(world),
      operators_(dynamics_),
      ties_(world),
      two_halves_(parameters_.two_halves && operators_.sparse() && !operators_.nonlinear() &&
                  world_.prescribed.empty() && ties_.empty()),
      stage_(world, parameters.solver, make_iteration()),
      sleep_(world, parameters.sleep),
      length_(world.length_scale()) {
  stage_.set_delassus_choice(parameters_.delassus_storage);
  if (sleep_.enabled()) {
    if (operators_.nonlinear())  // the scene loader refuses it first (integrator.sleep_speed)
      throw std::invalid_argument("sleeping bodies need a linear World (no finite-strain body)");
    stage_.set_asleep(&sleep_.asleep());
  }
  build_equalities(parameters_.step);
}

// The stage's view of A (iteration_operator.h); in two halves, the forward columns' operator, or for an A
// block diagonal by body the body blocks' (body_block_operator.h), which the step also drives (its forward
// and backward halves).
std::unique_ptr<IterationOperator> MoreauJean::make_iteration() {
  if (!two_halves_) return make_iteration_operator(operators_);
  std::unique_ptr<TwoHalvesOperator> halves;
  if (operators_.block_diagonal()) halves = std::make_unique<BodyBlockOperator>(operators_);
  else halves = std::make_unique<ForwardColumnsOperator>(operators_);
  halves_ = halves.get();
  return halves;
}

// The equality rows C v = target at t (s): the World's linear constraints, then the active prescriptions.
void MoreauJean::build_equalities(double t) {
  dynamics_.equality_rows(t, equalities_);
}

MoreauJean::~MoreauJean() = default;

void MoreauJean::summarize_settings(SummaryEntries& out) const {
  out.add("theta", parameters_.theta).add("close_gaps", parameters_.close_gaps);
}

void MoreauJean::summarize_statistics(const State& state, SummaryEntries& out) const {
  if (state.counters.newton_iterations > 0) add_newton_group(state.counters, parameters_.newton_tolerance, out);
  if (two_halves_)
    out.add("detections_retaken", state.counters.detections_retaken).add("sparse_solves", state.counters.sparse_solves)
        .add("dense_fallbacks", state.counters.dense_fallbacks);
  // Kept for the scripts that read it (docs/contract.md): every inelastic candidate is now a row from
  // the start, so no step's motion closes an inactive one.
  if (!operators_.nonlinear()) out.add("closing_activations", 0L);
  if (sleep_.enabled())
    out.begin_group("sleep")
        .add("asleep_at_end", sleep_.asleep_count())
        .add("islands_put_to_sleep", sleep_.islands_put_to_sleep())
        .add("islands_woken", sleep_.islands_woken())
        .end_group();
}

void MoreauJean::initialize(State& state) {
  if (!world_.prescribed.empty()) state.reactions.setZero(world_.velocity_size);
  state.energy.kinetic = state.energy.initial_kinetic = dynamics_.kinetic_energy(state.v);
  state.energy.elastic = state.energy.initial_elastic = dynamics_.elastic_energy(state.q);
}

// Loads at both ends of the step (their points taken at q_k), and the inertial force at v_k.
void MoreauJean::compute_loads(const State& state) {
  const double h = parameters_.step, theta = parameters_.theta;
  dynamics_.external(state.q, state.t + h, state.t, f_loads_, f_total_);
  f_loads_ *= theta;
  f_loads_ += (1.0 - theta) * f_total_;
  dynamics_.add_inertial_forces(state.v, f_loads_);
}

void MoreauJean::compute_free_velocity(const State& state) {
  const double h = parameters_.step, theta = parameters_.theta;
  compute_loads(state);
  f_total_ = f_loads_;
  // The forces before A's update: it compares the springs' Jacobian columns of the same evaluation.
  if (operators_.has_stiffness()) dynamics_.add_internal_forces(state.q, f_total_);
  operators_.update(state.q, h, theta);
  if (operators_.has_stiffness()) {
    if (!stiffness_velocity_kept(state.v)) {
      // K v_k as account_energy forms it for the next step where it keeps it (the same bits either way).
      if (keeps_stiffness_velocity()) dynamics_.apply_linear_stiffness(state.q, state.v, stiffness_velocity_);
      else operators_.apply_stiffness(state.v, stiffness_velocity_);
    }
    f_total_ -= (theta * h) * stiffness_velocity_;
  }
  // −C v_θ = −C v_k − θ C (v_{k+1} − v_k), the latter in W
  dynamics_.add_damping_force(state.v, f_total_);
  v_free_ = h * f_total_;
  if (two_halves_) {  // the forward half alone (see the header)
    halves_->forward_half(v_free_);
    check_free_velocity(v_free_, state.t + h);
    return;
  }
  operators_.solve_in_place(v_free_);
  v_free_ += state.v;
  check_free_velocity(v_free_, state.t + h);
}

bool MoreauJean::keeps_stiffness_velocity() const {
  return operators_.sparse() && operators_.has_stiffness() && dynamics_.constant_stiffness();
}

bool MoreauJean::stiffness_velocity_kept(const Vector& v) const {
  return keeps_stiffness_velocity() && kept_factorization_ == operators_.factorizations() &&
         kept_velocity_.size() == v.size() && same_bits(v.data(), kept_velocity_.data(), v.size());
}

void MoreauJean::check_free_velocity(const Vector& v_free, double t) const {
  if (!v_free.allFinite()) {
    std::ostringstream message;
    message << "non-finite free velocity at t = " << t
            << " s (forces or stiffness overflow: check the loads, masses and the time step)";
    throw RunError(t, message.str());
  }
}

void MoreauJean::detect(const State& state) {
  const double h = parameters_.step, theta = parameters_.theta;
  stage_.detect(state.q, detection_margin(state));
  // An asleep island that a moving body reaches wakes, and its pairs are then detected too.
  while (sleep_.wake_touched(stage_.candidates())) stage_.detect(state.q, detection_margin_);
  if (two_halves_) {  // every candidate's forward column (the equalities' too, without contacts)
    halves_->gather_candidates(stage_.candidates(), stage_.candidate_rows(), stage_.dimension(), &equalities_.rows);
    if (stage_.empty()) return;
  }
  const int d = stage_.dimension();
  const bool linear_closing = parameters_.close_gaps && !operators_.nonlinear();
  for (int k = 0; k < stage_.candidate_count(); ++k) {
    // A linear step that closes gaps makes every inelastic candidate a row (see the header, step 2).
    if (linear_closing && world_.contact_laws[stage_.candidates()[k].law].restitution == 0.0) {
      stage_.activate(k);
      continue;
    }
    // The normal velocity the contact would have over a free step (θ-weighted), so that a body at rest
    // under a load that presses it on the surface is caught at the first step, whatever the round-off
    // in its gap; in two halves from its forward column, u_n(v_θ,free) = u_n(v_k) + θ y_nᵀ z. A step
    // taken again over its converged motion (step_newton) also activates what that motion closes.
    const double predicted = two_halves_
                                 ? stage_.predicted_gap(k, state.v, kActivationGamma * h) +
                                       kActivationGamma * h * theta * halves_->free_dot(d * k)
                                 : stage_.predicted_gap(k, v_predicted_, kActivationGamma * h);
    if (predicted <= stage_.touching() ||
        (reach_velocity_.size() > 0 && stage_.predicted_gap(k, reach_velocity_, h) <= stage_.touching()))
      stage_.activate(k);
  }
}

// Broad-phase margin (m): twice the farthest any point can travel in the step.
double MoreauJean::detection_margin(const State& state) {
  if (stage_.empty()) return 0.0;
  const double h = parameters_.step, theta = parameters_.theta;
  const ContactDetector& detector = stage_.detector();
  double reach = 0.0;
  if (two_halves_ && !free_velocity_formed_) {
    // No v_free (see the header): twice the travel of the faster of v_k and the last step's v_θ, which
    // step_in_two_halves checks the step's motion against.
    reach = kReachGrowth * detector.travel_bound(state.v, h);
    if (v_theta_.size() == state.v.size()) reach = std::max(reach, kReachGrowth * detector.travel_bound(v_theta_, h));
    reach_ = reach;
  } else {
    // The θ-weighted velocity of a free step, v_θ = (1−θ)v_k + θ v_free, except on prescribed
    // components, which move as prescribed: (q_ref + value(t_{k+1}) − q_k) / h. A plate driven into a
    // body is then caught at its first step instead of penetrating by one step's travel.
    v_predicted_ = (1.0 - theta) * state.v + theta * v_free_;
    for (int p : equalities_.prescriptions) {
      const PrescribedComponent& c = world_.prescribed[p];
      const BodyInstance& b = world_.bodies[c.body];
      const int coordinate = b.body->coordinate_of(c.component);
      double& predicted = v_predicted_(b.velocity_offset + c.component);
      if (coordinate < 0)  // a 3D rotation: its rate
        predicted = (c.value(state.t + h) - c.value(state.t)) / h;
      else
        predicted = (b.reference_position(coordinate) + c.value(state.t + h) - state.q(b.position_offset + coordinate)) / h;
    }
    // Unprescribed, v_θ,free lies between v_k and v_free (θ ∈ [½, 1]), and a travel bound, convex in v,
    // is then at most the larger of theirs (to a rounding of the margin).
    reach = std::max(detector.travel_bound(state.v, h), detector.travel_bound(v_free_, h));
    if (!equalities_.prescriptions.empty()) reach = std::max(reach, detector.travel_bound(v_predicted_, h));
    if (reach_velocity_.size() > 0) reach = std::max(reach, detector.travel_bound(reach_velocity_, h));
  }
  return detection_margin_ = 2.0 * reach + 1e-12;
}

// Step 3: the rows, W by the stage, and b = H v_free + the impact law, gap closing and equality targets.
void MoreauJean::assemble(const State& state) {
  const double h = parameters_.step, theta = parameters_.theta;
  stage_.gather_rows(&equalities_.rows, &ties_.rows(), state.t + h);
  stage_.form_delassus();
  const ProblemRows& rows = stage_.rows();
  Vector& b = stage_.problem().b;
  if (two_halves_) {  // H v_free = H v_k + Yᵀ z (see the header)
    stage_.free_term(state.v);
    for (int a = 0; a < rows.size(); ++a) b(a) += halves_->free_dot(rows.candidate_row(a));
  } else {
    stage_.free_term(v_free_);
  }
  const int d = stage_.dimension();
  const std::vector<ActiveContact>& active = stage_.active();
  for (int i = 0; i < static_cast<int>(active.size()); ++i) {
    const double e = world_.contact_laws[active[i].law].restitution;
    const double approach = rows.dot(d * i, state.v);
    if (e > 0.0) {
      b(d * i) += e * approach;
    } else if (parameters_.close_gaps) {
      // An inelastic contact still open by g: its condition is g(q_{k+1}) ≥ 0, that is
      // u_n(v_{k+1}) ≥ −(g + h(1−θ) u_n(v_k)) / (hθ), so that it closes the gap within the step and
      // stops on the surface, not wherever the activation rule caught it (header, step 3). A gap
      // within the touching band counts as closed, g = 0: closing gaps of round-off would ask a
      // hyperstatic set for a rigid motion that closes every one of them at once, which their
      // round-off does not allow (a settled pile of 200 spheres: after 30 steps no impulse met the
      // law to better than a relative 1e-8, and Gauss–Seidel ran its 20 000 sweeps every step).
      const double gap = active[i].point.gap > stage_.touching() ? active[i].point.gap : 0.0;
      const double opening = gap + h * (1.0 - theta) * approach;
      if (opening > 0.0) b(d * i) += opening / (h * theta);
    }
  }
  const int first = rows.contact_rows(), ne = rows.equality_rows();
  for (int e = 0; e < ne; ++e) b(first + e) -= equality_target(state, e);
  for (int i = 0; i < ties_.size(); ++i) b(first + ne + i) -= tie_targets_(i);
}

// Step 5: v_{k+1} = v_free + A⁻¹ Hᵀ r (in two halves, v_k + A⁻¹ (h f + Hᵀ r) by the backward half).
void MoreauJean::update(State& state) {
  const double theta = parameters_.theta;
  if (two_halves_) {
    halves_->velocity(stage_.rows(), stage_.impulses(), state.v, v_next_);
  } else {
    v_next_ = v_free_;
    stage_.add_response(v_next_);
  }
  sleep_.hold_velocities(v_next_);  // v_k = 0 there too, so v_θ = 0
  v_theta_ = (1.0 - theta) * state.v + theta * v_next_;
  integrate_positions(state.q, v_theta_, q_next_);
  sleep_.hold_positions(state.q, q_next_);
}

// q + h v_θ body by body (a 3D rigid body's rotation through its quaternion; fixed bodies have no coordinates).
void MoreauJean::integrate_positions(const Vector& q, const Vector& v_theta, Vector& out) const {
  out.resize(q.size());
  for (const BodyInstance& b : world_.bodies) {
    if (b.body->fixed()) continue;
    b.body->integrate_position(b.positions(q), v_theta.segment(b.velocity_offset, b.body->velocity_size()),
                               parameters_.step, out.segment(b.position_offset, b.body->position_size()));
  }
}

void MoreauJean::account_energy(State& state) {
  const double h = parameters_.step, theta = parameters_.theta;
  EnergyBalance& e = state.energy;
  e.work_of_loads += h * f_loads_.dot(v_theta_);
  e.contact_dissipation -= stage_.impulse_work(v_theta_);
  // (θ−½)(|Δv|²_M + |Δq|²_K) is zero when θ = ½ whatever its factors: neither is formed then (the ±0
  // it would add leaves the sum as it is).
  if (theta != 0.5) dv_ = v_next_ - state.v;
  double kinetic = 0.0;
  if (keeps_stiffness_velocity()) {
    // A sparse linear World: the next step's K v_k, M v_{k+1}, M Δv into work_, and K q_{k+1} (the
    // elastic energy's, below) in one pass over K and M (linear_products.h).
    dynamics_.linear_products(q_next_, v_next_, theta == 0.5 ? nullptr : &dv_, stiffness_velocity_next_,
                              mass_velocity_, &work_);
    kinetic = 0.5 * v_next_.dot(mass_velocity_);
  } else if (theta == 0.5) {
    kinetic = operators_.kinetic_energy(v_next_, work_);
  } else {
    kinetic = operators_.kinetic_energy(v_next_, dv_, work_);  // and M Δv into work_
  }
  if (theta != 0.5) {
    double numerical = dv_.dot(work_);
    if (operators_.nonlinear()) {  // −Δq·(f(q_{k+1}) − f(q_k)), f at Newton's last iterate (see the header)
      numerical -= h * v_theta_.dot(f_iterate_ - f_start_);
    } else if (keeps_stiffness_velocity()) {
      // K v_θ = (1−θ) K v_k + θ K v_{k+1}: K v_k is the free velocity's, K v_{k+1} the next step's.
      work_ = (1.0 - theta) * stiffness_velocity_ + theta * stiffness_velocity_next_;
      numerical += h * h * v_theta_.dot(work_);
    } else if (operators_.has_stiffness()) {
      operators_.apply_stiffness(v_theta_, work_);
      numerical += h * h * v_theta_.dot(work_);
    }
    e.numerical_dissipation += (theta - 0.5) * numerical;
  }
  if (operators_.has_damping()) {
    operators_.apply_damping(v_theta_, work_);
    e.damping_dissipation += h * v_theta_.dot(work_);
  }
  e.kinetic = kinetic;
  e.elastic = dynamics_.elastic_energy(q_next_);
  e.max_abs_residual = std::max(e.max_abs_residual, std::abs(e.residual()));
}

// Steps 2 to 5 of a linear step, each phase timed.
void MoreauJean::detect_solve_update(State& state) {
  detect(state);
  clock_.lap(state.timers.detection);
  linearize_ties(state, state.v);
  assemble(state);
  clock_.lap(state.timers.assembly);
  stage_.solve(state.contacts, true, parameters_.failure_residual, state.t + parameters_.step, state.counters);
  clock_.lap(state.timers.solve);
  update(state);
}

// The inactive candidates whose gap the step's motion v_θ closes within `time` (s),
// g + time · u_n(v_θ) ≤ touching, activated now, in candidate order (Newton's missed contacts,
// moreau_jean_newton.cpp).
int MoreauJean::activate_closed_by_motion(double time) {
  std::vector<int> closed;
  for (int k = 0; k < stage_.candidate_count(); ++k) {
    if (stage_.is_active(k)) continue;
    if (stage_.predicted_gap(k, v_theta_, time) <= stage_.touching()) closed.push_back(k);
  }
  if (!closed.empty()) stage_.activate_more(closed);
  return static_cast<int>(closed.size());
}

// Two halves (see the header), after the forward half: detection, contact solve and the backward half
// without v_free; taken again with v_free formed if the step's motion went farther than the margin
// covered (the counters of the first solve are then dropped).
void MoreauJean::step_in_two_halves(State& state) {
  const double h = parameters_.step;
  const SolverCounters counted = state.counters;
  free_velocity_formed_ = false;
  detect_solve_update(state);
  if (stage_.empty() || stage_.detector().travel_bound(v_theta_, h) <= reach_) return;
  state.counters = counted;
  ++state.counters.detections_retaken;
  halves_->free_velocity(state.v, v_free_);
  check_free_velocity(v_free_, state.t + h);
  free_velocity_formed_ = true;
  detect_solve_update(state);
}

void MoreauJean::step(State& state) {
  // Phase timers (phase_clock.h): a linear World's step is timed on one step in kTimerSampling, the
  // last of each group, so that the first step's one-time work (the factorization, the contacts' first
  // Delassus entries) is not counted kTimerSampling times; a Newton step is timed whole.
  if (operators_.nonlinear()) clock_.start(true);
  else clock_.start(state.counters.steps % kTimerSampling == kTimerSampling - 1, kTimerSampling);
  // A prescription released over this step: its row goes.
  if (world_.releases_prescription(state.t, state.t + parameters_.step)) build_equalities(state.t + parameters_.step);
  if (operators_.nonlinear()) {
    step_newton(state);  // steps 1–5 in each Newton iteration (moreau_jean_newton.cpp)
  } else {
    compute_free_velocity(state);                      // 1
    clock_.lap(state.timers.free_velocity);
    if (two_halves_) step_in_two_halves(state);        // 2–5
    else detect_solve_update(state);
  }
  state.factorization_seconds = operators_.factorization_seconds();
  account_energy(state);                               // 6
  finish_step(state);
}

// The islands at rest fall asleep (sleeping_islands.h): the kinetic energy their zeroed velocities held
// is booked as dissipated by it, so that the balance still closes.
void MoreauJean::settle(State& state) {
  const bool fell_asleep = sleep_.settle(parameters_.step, state.t, state.contacts, state.v);
  state.counters.bodies_asleep = sleep_.asleep_count();
  if (!fell_asleep) return;
  const double kinetic = dynamics_.kinetic_energy(state.v);
  state.energy.sleep_dissipation += state.energy.kinetic - kinetic;
  state.energy.kinetic = kinetic;
}

// The new state: a non-finite check, the prescriptions' reactions, K v_{k+1} kept for the next step,
// the counters and the contact set (the next step's warm start).
void MoreauJean::finish_step(State& state) {
  const double h = parameters_.step;
  if (!v_next_.allFinite() || !q_next_.allFinite()) {
    std::ostringstream message;
    message << "non-finite state at t = " << state.t + h << " s (check the time step, stiffness and loads)";
    throw RunError(state.t + h, message.str());
  }
  if (!world_.prescribed.empty()) {  // the force each prescription exerted: its impulse / h
    state.reactions.setZero(world_.velocity_size);
    const int first = stage_.rows().contact_rows() + static_cast<int>(world_.constraints.size());
    for (std::size_t i = 0; i < equalities_.prescriptions.size(); ++i) {
      const PrescribedComponent& p = world_.prescribed[equalities_.prescriptions[i]];
      state.reactions(world_.bodies[p.body].velocity_offset + p.component) = stage_.impulses()(first + i) / h;
    }
  }
  if (keeps_stiffness_velocity()) {  // K v_{k+1} for the next step, while K stays
    stiffness_velocity_.swap(stiffness_velocity_next_);
    kept_velocity_ = v_next_;
    kept_factorization_ = operators_.factorizations();
  }
  state.q.swap(q_next_);
  state.v.swap(v_next_);
  SolverCounters& c = state.counters;
  ++c.steps;
  state.t = static_cast<double>(c.steps) * h;  // no accumulated round-off
  stage_.hand_over(state.contacts);
  if (sleep_.enabled()) settle(state);  // the list then holds the asleep islands' contacts too
  c.count_contacts(state.contacts);
  clock_.lap(state.timers.update);
}

}  // namespace csim
