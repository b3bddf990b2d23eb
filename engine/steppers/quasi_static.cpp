#include "engine/steppers/quasi_static.h"

#include "fem/mesh.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace csim {

namespace {

constexpr double kHubProximal = 1e-4;  // ε / max diag(K_z) on hub unknowns (see the header)
constexpr double kFirstHeld = 1e-4;    // the held rows' first ρ / max diag(K_z)
constexpr int kHeldRounds = 4;         // solves again after dropping let-go rows, at most
constexpr int kCompliancePasses = 20;  // penalty friction: solves again at the new normal forces, at most
constexpr double kComplianceTolerance = 1e-8;  // … until they change by less (over the largest)

ReducedCoordinates reduce(const World& world, double t) {
  try {
    return ReducedCoordinates(world, t);
  } catch (const std::invalid_argument& e) {
    throw RunError(0.0, std::string("quasi-static: ") + e.what());
  }
}

}  // namespace

std::string QuasiStatic::unsupported(const World& world) {
  if (!world.constraints.empty())
    return "quasi-static does not take linear constraints ('constraints'); use moreau-jean";
  try {
    return unsupported(world, ReducedCoordinates(world, 0.0));
  } catch (const std::invalid_argument& e) {
    return std::string("quasi-static: ") + e.what();
  }
}

// Every unknown of a lumped body needs stiffness: a spring, a tie, or a prescription.
std::string QuasiStatic::unsupported(const World& world, const ReducedCoordinates& reduced) {
  if (!world.springs.empty()) return "";
  for (const BodyInstance& b : world.bodies) {
    if (b.body->fixed() || b.body->elastic()) continue;
    bool held = false;
    for (const RigidTie& tie : world.ties) held = held || &world.bodies[tie.rigid_body] == &b;
    bool driven = true;
    for (int c = 0; c < b.body->velocity_size(); ++c) driven = driven && reduced.unknown(b.velocity_offset + c) < 0;
    if (!held && !driven)
      return "quasi-static: body '" + b.name +
             "' is held by no stiffness (its K would be singular): give it a spring, a tie or prescribed "
             "motions, or use moreau-jean";
  }
  return "";
}

QuasiStatic::QuasiStatic(const World& world, const QuasiStaticParameters& parameters)
    : world_(world), parameters_(parameters), dynamics_(world), reduced_(reduce(world, 0.0)),
      stage_(world, parameters.solver, make_operator()), d_(stage_.dimension()) {
  if (!world.constraints.empty()) throw RunError(0.0, unsupported(world));
  if (const std::string refusal = unsupported(world, reduced_); !refusal.empty()) throw RunError(0.0, refusal);
  stage_.set_delassus_choice(parameters.delassus_storage);
  bool nonlinear = false;
  for (const BodyInstance& b : world.bodies) nonlinear = nonlinear || b.body->nonlinear();
  for (const ContactLaw& law : world.contact_laws) penalty_friction_ = penalty_friction_ || law.elastic_slip > 0.0;
  linear_ = !nonlinear && world.ties.empty() && dynamics_.constant_spring_stiffness();
  length_ = world.length_scale();
  contact_distance_ = parameters.contact_distance > 0.0 ? parameters.contact_distance : 0.1 * length_;
}

// The stage's view of the stiffness (quasi_static_operator.h), whose two halves of a solve iterate() takes.
std::unique_ptr<IterationOperator> QuasiStatic::make_operator() {
  auto iteration = std::make_unique<QuasiStaticOperator>(factor_, T_);
  operator_ = iteration.get();
  return iteration;
}

void QuasiStatic::summarize_statistics(const State& state, SummaryEntries& out) const {
  add_newton_group(state.counters, parameters_.newton_tolerance, out);
  out.begin_group("complementarity")  // of the accepted iterates, in metres (see the header)
      .add("max_violation", max_complementarity_)
      .add("tolerance", parameters_.failure_residual * length_)
      .end_group();
}

void QuasiStatic::initialize(State& state) {
  state.energy.elastic = state.energy.initial_elastic = dynamics_.elastic_energy(state.q);
  state.reactions.setZero(world_.velocity_size);
}

// f(q, t): loads, springs and the bodies' internal forces (N, N·m), in q's components; and, when the
// tangent is needed, the bodies' tangent stiffness into triplets_ in the same pass over the elements.
// A finite-strain body riding in its hub's frame is evaluated there (its energy is objective): its force
// turned to the world, its tangent left in the frame, first in triplets_, as reduce_stiffness takes it
// (reduced_coordinates.h). Returns where the world-frame entries of triplets_ start.
std::size_t QuasiStatic::generalized_force(const Vector& q, double t, Vector& f, bool tangent) {
  dynamics_.external(q, t, f);
  triplets_.clear();
  return dynamics_.add_internal_forces_and_tangent(q, f, tangent && needs_tangent() ? &triplets_ : nullptr, &reduced_);
}

// K_z from the bodies' tangent (in triplets_, from generalized_force) and the springs'; factored by
// factor_stiffness once the contacts and their warm start are known.
void QuasiStatic::assemble_stiffness(const Vector& q, std::size_t world_from) {
  if (!needs_tangent()) return;
  // The frame's geometric stiffness with the loads and internal forces; the contact forces' part is
  // added by factor_stiffness when held rows balance it (see the header).
  reduced_.reduce_stiffness(q, f_, triplets_, world_from, K_z_);
}

double QuasiStatic::iterate(const State& state, double t_next) {
  t_ = t_next;
  if (needs_tangent()) reduced_.tangent(q_, T_);
  clock_.lap(timers_.free_velocity);
  // A linear World's contact geometry is the step start's (see the header): the later iterates that soft
  // directions need shift its offsets.
  if (linear_ && iteration_ > 0) shift_contact_offsets(state);
  else detect_contacts(state, t_next);
  clock_.lap(timers_.detection);
  stage_.warm_start_from(previous_, &warm_status_);
  soften_friction(state);
  hold_.assign(stage_.active().size(), Hold::none);
  for (int i = 0; i < static_cast<int>(hold_.size()); ++i)
    if (stage_.impulses()(d_ * i) > 0.0) hold_[i] = warm_status_[i] == ContactStatus::stick ? Hold::stick : Hold::normal;
  clock_.lap(timers_.assembly);
  // Modified Newton (see the header): the forces alone when an earlier iterate's factor is kept.
  bool keep = accelerated_ && parameters_.modified_newton && !linear_ &&
              kept_.fits(held_rows(), held_weight_, hub_proximal_, !reduced_.hub_unknowns().empty());
  const std::size_t world_from = generalized_force(q_, t_next, f_, !keep);
  f_z_ = reduced_.identity() ? f_ : Vector(T_.transpose() * f_);
  if (!keep) assemble_stiffness(q_, world_from);
  clock_.lap(timers_.free_velocity);
  const bool held = solve_contact_problem(t_next, keep);
  if (!keep)
    kept_.record({held ? KeptFactor::Kind::held : factor_kind_, held_rows(), held_weight_, hub_proximal_, held_rho_,
                  factor_regularized_});
  // Δz = K⁻¹ (f_aug + H_zᵀ r), the second half of assemble_problem's solve (f_aug_ unchanged since).
  if (stage_.problem().size() > 0) operator_->increment(stage_.impulses(), dz_);
  else dz_ = factor_.solve(f_aug_);
  // Reactions of the prescriptions at q_j: −(f + Hᵀ r) on their components.
  update_contact_force();
  reduced_.prescribed_forces(q_, f_ + contact_force_, reactions_);
  reactions_ = -reactions_;
  // Not in a linear World (one iteration): secant_relaxation.h
  const double relaxation = linear_ ? 1.0 : relaxation_.next(dz_);
  if (relaxation != 1.0) ++counters_->newton_relaxed;
  reduced_.gather(q_, t_next, z_);  // at q_j, so that T is exact there (3D rotations: increments)
  z_ += relaxation * dz_;
  z_increment_ += relaxation * dz_;
  reduced_.expand(z_, t_next, q_);
  if (!q_.allFinite()) throw RunError(t_next, "quasi-static: non-finite displacement");
  previous_ = stage_.active();  // forces, for the next iteration's warm start
  clock_.lap(timers_.update);
  const double increment = dz_.size() > 0 ? dz_.lpNorm<Eigen::Infinity>() : 0.0;
  kept_.observe(increment, keep, relaxation == 1.0);
  return increment;
}

bool QuasiStatic::solve_contact_problem(double t_next, bool& keep) {
  // Held rows that the solve lets go would make the step another than Newton's (see the header): the
  // rows are dropped and the problem solved again, a few times at most.
  bool held = false;
  for (int round = 0;; ++round) {
    if (keep) {
      held = kept_.made().kind == KeptFactor::Kind::held;
      f_aug_ = held ? Vector(f_z_ - kept_.made().rho * held_load()) : f_z_;
    } else {
      held = factor_stiffness();
    }
    if (round == 0) {
      if (held) ++counters_->newton_held;
      if (keep) ++counters_->newton_kept_factor;
      if (keep && kept_.made().regularized) ++counters_->newton_regularized;
    }
    clock_.lap(timers_.free_velocity);
    assemble_problem();
    clock_.lap(timers_.assembly);
    // A contact solve that fails at an iterate far from equilibrium (the hub spun far in the spin-up:
    // gaps of −0.14) need not stop the run: the next iterate solves again. The accepted iterate's must
    // not fail (solve_increment).
    contact_failure_ = stage_.solve_from_impulses(parameters_.failure_residual, t_next, *counters_);
    // Penalty friction's compliance at the normal forces just found, to its fixed point (a linear World
    // takes a single iterate: the warm start's, the last step's, would leave it a step behind).
    for (int pass = 0; penalty_friction_ && pass < kCompliancePasses; ++pass) {
      const Vector used = compliance_;
      if (set_compliance(stage_.impulses()) <= kComplianceTolerance) break;
      stage_.problem().W.diagonal() += compliance_ - used;
      contact_failure_ = stage_.solve_from_impulses(parameters_.failure_residual, t_next, *counters_);
    }
    // A failed solve is taken again with a stiffer hold of the rows or the hub (×100, up to max diag),
    // kept for the step's later iterates: each failed solve costs max_iterations sweeps.
    // On the proximal path the hub's spin is nearly free (ε = 1e-4 max diag), so a contact a
    // distance x from the bottom gets a normal compliance ~x²/ε and a coupling to its own tangent
    // ~R x/ε: for |x| < μR, friction makes the effective normal compliance of a slip negative, a
    // Painlevé-like problem that no contact solver finishes (3D elastic ring r_i 1, δ 0.1 on 34 × 5 at
    // t = 1.64: the contact next to the bottom has W_nn = 0.0315 and μ|W_nt| = 0.0316; residual 1.6e-3
    // after 20000 sweeps). A stiffer hub makes it well posed; the iterate then only moves the spin less
    // far. On held rows, sticking contacts coupled to the nearly free spin meet the same μ|W_nt| ≈ W_nn;
    // a larger ρ shrinks W along the rows and leaves the step Newton's while they stay held.
    clock_.lap(timers_.solve);
    double& weight = held ? held_weight_ : hub_proximal_;
    const bool stiffer = !contact_failure_.empty() && (held || !reduced_.hub_unknowns().empty()) && weight < 1.0;
    if (stiffer) weight *= 100.0;
    else if (!held || round == kHeldRounds || !release_let_go_rows()) break;
    if (keep) {  // the kept factor holds other rows, or with another weight: this iterate's own tangent
      keep = false;
      assemble_stiffness(q_, generalized_force(q_, t_next, f_, true));
      clock_.lap(timers_.free_velocity);
    }
  }
  return held;
}

void QuasiStatic::step(State& state) {
  const double h = parameters_.step;
  const double t_next = static_cast<double>(state.counters.steps + 1) * h;
  counters_ = &state.counters;
  const Vector q_start = state.q;
  clock_.start(true);
  advance(state, t_next, 0);
  state.timers = timers_;
  SolverCounters& c = state.counters;
  world_.position_difference(state.q, q_start, state.v);
  state.v /= h;
  ++c.steps;
  c.count_contacts(state.contacts);
}

void QuasiStatic::measure_energy(State& state) const { state.energy.elastic = dynamics_.elastic_energy(state.q); }

// Brings state to t_next; when Newton fails, as two halves, each of which may be halved again, down
// to max_cutbacks halvings (the loading path is a function of t, so any t in between is a load step).
void QuasiStatic::advance(State& state, double t_next, int halvings) {
  std::string failure = solve_increment(state, t_next, true);
  // The predictor and the kept factor change the iterates: a step they did not bring to convergence is
  // first taken again with neither (see the header).
  if (!failure.empty() && !linear_ && (parameters_.predictor || parameters_.modified_newton))
    failure = solve_increment(state, t_next, false);
  if (failure.empty()) {
    accept(state, t_next);
    return;
  }
  if (linear_ || halvings >= parameters_.max_cutbacks) {
    std::ostringstream message;
    message << failure;
    if (halvings > 0)
      message << " (step halved " << halvings << " times, to " << t_next - state.t
              << " s; integrator.max_cutbacks)";
    throw RunError(t_next, message.str());
  }
  ++state.counters.cutbacks;
  const double t_half = 0.5 * (state.t + t_next);
  advance(state, t_half, halvings + 1);
  advance(state, t_next, halvings + 1);
}

// Newton's iterations from state to t_next into q_, the stage's contacts and reactions_; state is not touched. Returns
// "" when they converged, else why not.
std::string QuasiStatic::solve_increment(const State& state, double t_next, bool accelerated) {
  accelerated_ = accelerated;
  // The prescriptions in force at t_next (a cutback can step back across a release).
  if (world_.releases_prescription(reduced_time_, t_next) || world_.releases_prescription(t_next, reduced_time_)) {
    reduced_ = reduce(world_, t_next);
    reduced_time_ = t_next;
    factored_ = false;
    last_z_increment_.resize(0);  // another set of unknowns
  }
  reduced_.gather(state.q, state.t, z_);
  // The predictor: the last accepted step's increment of z, scaled to this step's length (see the header).
  z_increment_.setZero(z_.size());
  if (accelerated_ && parameters_.predictor && !linear_ && last_z_increment_.size() == z_.size() && last_step_length_ > 0.0)
    z_increment_ = ((t_next - state.t) / last_step_length_) * last_z_increment_;
  z_ += z_increment_;
  reduced_.expand(z_, t_next, q_);
  // The warm start: the last increment's forces (state's impulses are forces × h, see accept).
  previous_ = state.contacts;
  for (ActiveContact& c : previous_) c.impulse /= parameters_.step;

  SolverCounters& c = *counters_;
  int iterations = 0;
  double increment = 0.0;
  relaxation_.reset();
  kept_.drop();
  hub_proximal_ = kHubProximal;
  held_weight_ = kFirstHeld;
  std::string failure;
  for (iteration_ = 0;; ++iteration_) {
    try {
      increment = iterate(state, t_next);
    } catch (const FemError& e) {  // an element inverted at this iterate: a shorter increment may not
      failure = "quasi-static Newton iteration " + std::to_string(iterations + 1) + ": " + e.what();
    } catch (const RunError& e) {  // a non-finite or indefinite iterate
      failure = e.what();
    }
    ++iterations;
    if (!failure.empty()) break;
    const double tolerance = parameters_.newton_tolerance * length_;
    if ((linear_ && soft_unknowns_.empty()) || increment <= tolerance || kept_.distance_bound() <= tolerance) {
      failure = contact_failure_;
      if (failure.empty()) failure = complementarity_failure(t_next);
      if (failure.empty()) failure = unheld_directions(t_next);
      break;
    }
    if (iterations >= parameters_.newton_max_iterations) {
      std::ostringstream message;
      message << "quasi-static: Newton did not converge at t = " << t_next << " s: |dz| = " << increment
              << " after " << iterations << " iterations (tolerance " << parameters_.newton_tolerance * length_
              << "; integrator.newton_max_iterations, or a smaller time.step)";
      if (!contact_failure_.empty()) message << "; its last " << contact_failure_;
      if (!soft_unknowns_.empty())
        message << "; the stiffness holds a mode of " << soft_directions() << " by less than " << kSingularPivot
                << " of its own stiffness (a rigid-body mode held by no spring, or by one round-off cannot tell from "
                   "none), which the iterates hold by a proximal term: when the contacts do not hold it either, fix "
                   "or prescribe components of that body, or give it a spring of stiffness comparable to its own";
      failure = message.str();
      break;
    }
  }
  c.newton_iterations += iterations;
  c.max_newton_iterations = std::max(c.max_newton_iterations, iterations);
  return failure;
}

// state ← the converged increment to t_next. Impulses are the forces × the whole step h, whatever the
// increment's length, so that contact-force probes read forces (state.h); points and gaps are those of
// the converged configuration, the last detection's carried by the last iterate's increment.
void QuasiStatic::accept(State& state, double t_next) {
  last_z_increment_ = z_increment_;
  last_step_length_ = t_next - state.t;
  state.q = q_;
  state.reactions = reactions_;
  state.t = t_next;
  state.contacts.clear();
  Vector motion;
  if (!stage_.active().empty()) world_.position_difference(q_, q_detected_, motion);
  for (const ActiveContact& solved : stage_.active()) {
    if (!(solved.impulse(0) > 0.0)) continue;  // open candidates are not contacts
    ActiveContact& contact = state.contacts.emplace_back(solved);
    contact.impulse *= parameters_.step;
    stage_.detector().move_contact(q_detected_, motion, contact.point);
  }
}

}  // namespace csim
