#include "engine/steppers/quasi_static.h"

#include "engine/linear_algebra/sparse_assembly.h"
#include "engine/contact_stage/contact_solve.h"
#include "engine/steppers/proximal.h"
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
constexpr double kSingularPivot = 1e-10;  // a pivot D_j ≤ this × K_jj: a direction K does not hold (see the header)
constexpr double kSoftProximal = 1e-6;    // ε / K_jj on such a direction's unknown
constexpr int kSoftRounds = 8;            // refactorizations that may find further such directions

// values ← S's entries at their places in pattern's values array (zero elsewhere); false when an entry
// of S falls outside pattern (compressed, rows sorted in each column, as setFromTriplets leaves them).
bool values_in_pattern(const SparseMatrix& pattern, const SparseMatrix& S, Vector& values) {
  values.setZero(pattern.nonZeros());
  const int* inner = pattern.innerIndexPtr();
  for (int j = 0; j < S.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(S, j); it; ++it) {
      const int* first = inner + pattern.outerIndexPtr()[j];
      const int* last = inner + pattern.outerIndexPtr()[j + 1];
      const int* found = std::lower_bound(first, last, static_cast<int>(it.row()));
      if (found == last || *found != it.row()) return false;
      values(found - inner) = it.value();
    }
  return true;
}

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

// Factors K_z, made positive definite when it is not or, with a hub, cannot be (see the header): by the
// held rows (hold_; ρ from held_weight_ · max diag), else by proximal terms (first hub_proximal_ · max diag
// on the hub's unknowns). Sets f_aug_, the load that goes with the factored matrix (Tᵀ f, less ρ H_Aᵀ c_A
// with held rows). Returns whether held rows were used.
bool QuasiStatic::factor_stiffness() {
  f_aug_ = f_z_;
  factor_kind_ = KeptFactor::Kind::stiffness;
  factor_regularized_ = false;
  if (!needs_tangent()) {  // a linear World's factor, made once
    if (!soft_unknowns_.empty()) ++counters_->newton_regularized;
    return false;
  }
  factored_ = true;
  soft_unknowns_.clear();
  const bool hub = !reduced_.hub_unknowns().empty();
  if (!hub) {
    const bool positive = factor_.factor_positive_definite(K_z_);
    // An indefinite tangent of a nonlinear body (a material instability, a compressed ring's sway) is
    // held below; a linear World's K is positive semidefinite, so that a pivot ≤ 0 is a mechanism.
    if ((positive || linear_) && hold_soft_directions()) return false;
  }
  if (linear_)
    throw RunError(t_, "quasi-static: the stiffness is singular (a free body or a rigid-body mode is not held by "
                       "springs, ties, prescribed components or fixed degrees of freedom)");
  const double largest = K_z_.diagonal().cwiseAbs().maxCoeff();
  Triplets augmented;
  for (int i = 0; i < static_cast<int>(hold_.size()); ++i)
    for (int a = d_ * i; a < d_ * i + held_row_count(hold_[i], d_); ++a) add_row_product(a, 1.0, augmented);
  // A hub needs a sticking contact to hold its spin; without, its proximal term.
  if (!augmented.empty() && rows_hold(held_rows(), hub)) {
    SparseMatrix HtH(K_z_.rows(), K_z_.cols());
    HtH.setFromTriplets(augmented.begin(), augmented.end());
    SparseMatrix G;
    bool geometric = false;
    if (hub) {
      update_contact_force();  // the warm start's, or the last round's
      geometric = reduced_.geometric_stiffness(q_, contact_force_, G);
    }
    // K_z + G + ρ HᵀH on K_z's own pattern, value by value, when G and HᵀH fall inside it (a node
    // contact's rows sit in its node's block and the hub's columns): the same sums as the sparse ones
    // below, without merging patterns at every ρ.
    const bool in_pattern =
        values_in_pattern(K_z_, HtH, held_values_) && (!geometric || values_in_pattern(K_z_, G, geometric_values_));
    SparseMatrix base;  // K_z + G, summed sparse when G or HᵀH leave K_z's pattern
    if (in_pattern) {
      if (!same_pattern(held_matrix_, K_z_)) held_matrix_ = K_z_;
      const Eigen::Map<const Vector> stiffness(K_z_.valuePtr(), K_z_.nonZeros());
      base_values_ = geometric ? Vector(stiffness + geometric_values_) : Vector(stiffness);
    } else {
      base = K_z_;
      if (geometric) base += G;
    }
    for (double rho = held_weight_ * largest; rho <= 10.0 * largest; rho *= 10.0) {
      if (in_pattern) Eigen::Map<Vector>(held_matrix_.valuePtr(), held_matrix_.nonZeros()) = base_values_ + rho * held_values_;
      else held_matrix_ = base + rho * HtH;
      if (factor_.factor_positive_definite(held_matrix_)) {
        f_aug_ = f_z_ - rho * held_load();
        held_rho_ = rho;
        return true;
      }
    }
  }
  factor_kind_ = KeptFactor::Kind::proximal;
  SparseMatrix proximal = K_z_;
  for (int i : reduced_.hub_unknowns()) proximal.coeffRef(i, i) += hub_proximal_ * largest;
  if (factor_.factor_positive_definite(proximal)) return false;
  double added = 0.0;
  const bool held = grow_proximal_term(largest, [&](double epsilon) {
    for (int i = 0; i < proximal.rows(); ++i) proximal.coeffRef(i, i) += epsilon - added;
    added = epsilon;
    return factor_.factor_positive_definite(proximal);
  });
  if (!held)
    throw RunError(t_, "quasi-static: the tangent stiffness stays indefinite (a rigid-body mode not held, or a "
                       "material instability)");
  ++counters_->newton_regularized;
  factor_regularized_ = true;
  return false;
}

// After factor_ of K_z_: the directions K_z holds by at most kSingularPivot of their own stiffness (their
// pivot, SparseLdlt::small_pivots: a rigid-body mode held by a spring that round-off cannot tell from
// none, or by none) get proximal terms ε = kSoftProximal · K_jj on their pivot's unknown, factored again
// until no pivot is small (see the header). Returns false when K_z stays singular (a direction that ε
// cannot reach in kSoftRounds rounds).
bool QuasiStatic::hold_soft_directions() {
  const Vector diagonal = K_z_.diagonal();
  std::vector<int> soft = factor_.small_pivots(diagonal, kSingularPivot);
  if (soft.empty()) return true;
  const double largest = diagonal.cwiseAbs().maxCoeff();
  SparseMatrix held = K_z_;
  for (int round = 0; round < kSoftRounds && !soft.empty(); ++round) {
    for (int j : soft) {
      held.coeffRef(j, j) += kSoftProximal * (diagonal(j) > 0.0 ? diagonal(j) : largest);
      soft_unknowns_.push_back(j);
    }
    factor_.factor_positive_definite(held);
    soft = factor_.small_pivots(held.diagonal(), kSingularPivot);
  }
  if (!soft.empty()) {
    soft_unknowns_.clear();
    return false;
  }
  factor_regularized_ = true;
  ++counters_->newton_regularized;
  return true;
}

// "body 'NAME' (its pivot at node N y)" (or a rigid body's component) for an unknown of z, for messages: a
// small pivot's unknown is the last of its mode in the factor's order, not the component the mode moves.
std::string QuasiStatic::describe_unknown(int unknown) const {
  static const char* const axes[] = {"x", "y", "z"};
  for (const BodyInstance& b : world_.bodies)
    for (int c = 0; c < b.body->velocity_size(); ++c) {
      if (reduced_.unknown(b.velocity_offset + c) != unknown) continue;
      std::ostringstream name;
      name << "body '" << b.name << "' ";
      if (b.body->elastic()) name << "(its pivot at node " << c / d_ << " " << axes[c % d_] << ")";
      else name << "(its pivot at component " << c << ")";
      return name.str();
    }
  return "unknown " + std::to_string(unknown);
}

void QuasiStatic::update_contact_force() {
  contact_force_.setZero(f_.size());
  const Vector& r = stage_.impulses();
  for (int a = 0; a < r.size(); ++a) stage_.rows().scatter(a, r(a), contact_force_);
}

// scale · h_aᵀ h_a, h_a row a of H_z, into triplets (the held rows' ρ H_Aᵀ H_A).
void QuasiStatic::add_row_product(int a, double scale, Triplets& triplets) {
  const Matrix& H = operator_->reduced_rows();
  row_unknowns_.clear();
  for (int k = 0; k < H.cols(); ++k)
    if (H(a, k) != 0.0) row_unknowns_.push_back(k);
  for (int k : row_unknowns_)
    for (int l : row_unknowns_) triplets.emplace_back(k, l, scale * H(a, k) * H(a, l));
}

// Drops from hold_ the rows the last solve let go (an opened contact, a sticking one that slips);
// false when every held row stayed held, so that the step was Newton's own.
bool QuasiStatic::release_let_go_rows() {
  bool released = false;
  for (int i = 0; i < static_cast<int>(hold_.size()); ++i) {
    const ContactStatus status = stage_.active()[i].status;
    const Hold keep = status == ContactStatus::open ? Hold::none : status == ContactStatus::slip ? Hold::normal : Hold::stick;
    if (hold_[i] > keep) {
      hold_[i] = keep;
      released = true;
    }
  }
  return released;
}

// The candidate contacts at q_j, all active, their rows over z (H_z = H T, the stage's operator) and
// offsets c (gap, slip since q_k).
void QuasiStatic::detect_contacts(const State& state, double t_next) {
  stage_.detect(q_, contact_distance_);
  for (int k = 0; k < stage_.candidate_count(); ++k) stage_.activate(k);
  stage_.gather_rows(nullptr, nullptr, t_next);
  q_detected_ = q_;
  const int m = stage_.problem().size();
  offset_.setZero(m);
  if (m == 0) return;
  world_.position_difference(q_, state.q, step_increment_);
  const std::vector<ActiveContact>& active = stage_.active();
  for (int i = 0; i < static_cast<int>(active.size()); ++i) {
    offset_(d_ * i) = active[i].point.gap;
    // The slip since the step start: the rows over q, before T.
    for (int k = 1; k < d_; ++k) offset_(d_ * i + k) = stage_.rows().dot(d_ * i + k, step_increment_);
  }
}

// Penalty friction's offset −γ φ_k on the tangential rows and its compliance at the warm start's normal
// forces (see the header).
void QuasiStatic::soften_friction(const State& state) {
  const std::vector<ActiveContact>& active = stage_.active();
  compliance_.setZero(stage_.problem().size());
  if (!penalty_friction_) return;
  compliance_normal_.setZero(active.size());
  warm_start(state.contacts, active, d_, stage_.problem().size(), start_impulse_);
  for (int i = 0; i < static_cast<int>(active.size()); ++i) {
    const ContactLaw& law = world_.contact_laws[active[i].law];
    const double start_normal = start_impulse_(d_ * i);
    const Eigen::Vector2d start_mu = law.mu_at(state.t);
    for (int k = 1; k < d_; ++k)  // φ_k from impulses: the step's h cancels in the ratio
      if (law.elastic_slip > 0.0 && start_normal > 0.0 && start_mu(k - 1) > 0.0)
        offset_(d_ * i + k) -= law.elastic_slip * start_impulse_(d_ * i + k) / (start_mu(k - 1) * start_normal);
  }
  set_compliance(stage_.impulses());
}

// compliance_ ← γ/(μ r_n) at the normal forces of r (m/N); a contact without a normal force there gets no
// friction. Returns the largest change of a normal force from the last call's, over the largest (0 when
// the compliance is exact for r).
double QuasiStatic::set_compliance(const Vector& r) {
  double change = 0.0, largest = 0.0;
  FrictionContactProblem& problem = stage_.problem();
  for (int i = 0; i < problem.contacts; ++i) {
    const ContactLaw& law = world_.contact_laws[stage_.active()[i].law];
    const double gamma = law.elastic_slip, normal = r(d_ * i);
    if (gamma <= 0.0) continue;
    const Eigen::Vector2d mu = law.mu_at(t_);  // detect_contacts' μ, which this may have zeroed
    largest = std::max(largest, normal);
    change = std::max(change, std::abs(normal - compliance_normal_(i)));
    compliance_normal_(i) = normal;
    for (int k = 1; k < d_; ++k) {
      problem.mu[i](k - 1) = normal > 0.0 ? mu(k - 1) : 0.0;
      compliance_(d_ * i + k) = normal > 0.0 && mu(k - 1) > 0.0 ? gamma / (mu(k - 1) * normal) : 0.0;
    }
  }
  return largest > 0.0 ? change / largest : 0.0;
}

// u = W r + b with the factored stiffness: W = H_z K⁻¹ H_zᵀ, b = H_z K⁻¹ f_aug + c (the stage's W, the
// operator's first half of the solve).
void QuasiStatic::assemble_problem() {
  FrictionContactProblem& problem = stage_.problem();
  const int m = problem.size();
  problem.W.resize(m, m);
  problem.b.resize(m);
  if (m == 0) return;
  stage_.form_delassus();
  operator_->load_term(f_aug_, problem.b);
  problem.b += offset_;
  problem.W.diagonal() += compliance_;
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
  std::size_t world_from = generalized_force(q_, t_next, f_, !keep);
  f_z_ = reduced_.identity() ? f_ : Vector(T_.transpose() * f_);
  if (!keep) assemble_stiffness(q_, world_from);
  clock_.lap(timers_.free_velocity);
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
      world_from = generalized_force(q_, t_next, f_, true);
      assemble_stiffness(q_, world_from);
      clock_.lap(timers_.free_velocity);
    }
  }
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

// A linear World's later iterate: the step start's contacts and rows, their offsets at q_j (the gap
// g_k + H_n (q_j ⊖ q_k), the slip H_t (q_j ⊖ q_k)), as detect_contacts would give them for a plane.
void QuasiStatic::shift_contact_offsets(const State& state) {
  const std::vector<ActiveContact>& active = stage_.active();
  if (active.empty()) return;
  world_.position_difference(q_, state.q, step_increment_);
  const ProblemRows& rows = stage_.rows();
  for (int i = 0; i < static_cast<int>(active.size()); ++i) {
    offset_(d_ * i) = active[i].point.gap + rows.dot(d_ * i, step_increment_);
    for (int k = 1; k < d_; ++k) offset_(d_ * i + k) = rows.dot(d_ * i + k, step_increment_);
  }
}

// complementarity_ ← the last iterate's violation of Signorini's law measured on the configuration it
// reaches, u = c + H_z Δz computed from Δz (not through W, whose round-off it would share), in metres: a
// penetration −u_n > 0, and an open gap u_n > 0 under a normal force r_n > 0, as min(u_n, r_n / max r_n · L)
// (a force at round-off of the largest does not count). Zero for an exact solution whatever W's scaling.
void QuasiStatic::measure_complementarity() {
  complementarity_ = 0.0;
  complementarity_contact_ = -1;
  const int nc = static_cast<int>(stage_.active().size());
  if (nc == 0) return;
  const Vector u = offset_ + operator_->reduced_rows() * dz_;
  const Vector& r = stage_.impulses();
  double largest = 0.0;
  for (int i = 0; i < nc; ++i) largest = std::max(largest, r(d_ * i));
  for (int i = 0; i < nc; ++i) {
    const double gap = u(d_ * i), force = r(d_ * i);
    double violation = std::max(0.0, -gap);
    if (gap > 0.0 && force > 0.0 && largest > 0.0) violation = std::min(gap, force / largest * length_);
    if (violation > complementarity_) {
      complementarity_ = violation;
      complementarity_contact_ = i;
      complementarity_gap_ = gap;
      complementarity_force_ = force;
    }
  }
}

HeldRows QuasiStatic::held_rows() const {
  HeldRows rows;
  for (int i = 0; i < static_cast<int>(hold_.size()); ++i)
    if (hold_[i] != Hold::none) rows.emplace_back(stage_.active()[i].point.key, hold_[i]);
  return rows;
}

// H_Aᵀ c̃_A over the held rows (hold_), c̃ the offset of ũ with penalty friction: ρ times it leaves the
// load with the held matrix (see the header).
Vector QuasiStatic::held_load() const {
  Vector load = Vector::Zero(f_z_.size());
  const Matrix& H = operator_->reduced_rows();
  const Vector& r = stage_.impulses();
  for (int i = 0; i < static_cast<int>(hold_.size()); ++i) {
    for (int a = d_ * i; a < d_ * i + held_row_count(hold_[i], d_); ++a)
      for (int k = 0; k < H.cols(); ++k)
        if (H(a, k) != 0.0) load(k) += H(a, k) * (offset_(a) + compliance_(a) * r(a));
  }
  return load;
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
  c.contact_points += static_cast<long>(state.contacts.size());
  c.max_contact_points = std::max(c.max_contact_points, static_cast<int>(state.contacts.size()));
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

// "" when the accepted iterate's contacts meet Signorini's law to failure_residual · L on the
// configuration it reaches (measure_complementarity), else the message that stops the step.
std::string QuasiStatic::complementarity_failure(double t_next) {
  measure_complementarity();
  max_complementarity_ = std::max(max_complementarity_, complementarity_);
  if (complementarity_ <= parameters_.failure_residual * length_) return "";
  const ActiveContact& contact = stage_.active()[complementarity_contact_];
  std::ostringstream message;
  message << "quasi-static: the contact solution at t = " << t_next << " s violates complementarity by "
          << complementarity_ << " m (tolerance contact_solver.failure_residual x L = "
          << parameters_.failure_residual * length_ << " m): a contact point of '"
          << world_.contact_laws[contact.law].name << "' ends with the gap " << complementarity_gap_
          << " m under the normal force " << complementarity_force_ << " N";
  if (!soft_unknowns_.empty()) message << " (the stiffness holds a mode of " << soft_directions() << " only by a proximal term)";
  return message.str();
}

// "" when the soft directions (soft_unknowns_) are held at the accepted iterate by K_z with its closed
// contacts' rows (the normal rows of contacts with a normal force, the tangential ones of those that
// stick): K_z + ρ H_Aᵀ H_A, ρ = max diag(K_z), has no small pivot. Otherwise a mode that nothing holds,
// whose position the proximal terms chose: the message that refuses it, naming where.
std::string QuasiStatic::unheld_directions(double t_next) {
  if (soft_unknowns_.empty()) return "";
  const double rho = K_z_.diagonal().cwiseAbs().maxCoeff();
  Triplets held;
  const std::vector<ActiveContact>& active = stage_.active();
  for (int i = 0; i < static_cast<int>(active.size()); ++i) {
    if (!(stage_.impulses()(d_ * i) > 0.0)) continue;
    const int rows = active[i].status == ContactStatus::stick ? d_ : 1;
    for (int a = d_ * i; a < d_ * i + rows; ++a) add_row_product(a, rho, held);
  }
  SparseMatrix with_contacts(K_z_.rows(), K_z_.cols());
  with_contacts.setFromTriplets(held.begin(), held.end());
  with_contacts += K_z_;
  hold_check_.factor_positive_definite(with_contacts);
  std::vector<int> unheld = hold_check_.small_pivots(with_contacts.diagonal(), kSingularPivot);
  if (unheld.empty()) return "";
  soft_unknowns_ = unheld;
  std::ostringstream message;
  message << "quasi-static: at t = " << t_next << " s, a mode of " << soft_directions()
          << " that neither the stiffness (its pivot is below " << kSingularPivot
          << " of its diagonal: a rigid-body mode held by no spring, or by one too weak to count) nor the closed "
             "contacts hold; fix or prescribe components of that body, give it a spring, or use moreau-jean";
  return message.str();
}

// The soft directions' unknowns, named (at most three), for messages.
std::string QuasiStatic::soft_directions() const {
  std::ostringstream names;
  for (std::size_t k = 0; k < soft_unknowns_.size() && k < 3; ++k)
    names << (k > 0 ? ", " : "") << describe_unknown(soft_unknowns_[k]);
  if (soft_unknowns_.size() > 3) names << " and " << soft_unknowns_.size() - 3 << " more";
  return names.str();
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
