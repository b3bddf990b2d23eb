#include "engine/steppers/moreau_jean.h"

#include "engine/linear_algebra/same_bits.h"
#include "engine/linear_algebra/small_dense_products.h"
#include "engine/contact_stage/contact_solve.h"
#include "fem/mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace csim {

namespace {

constexpr int kNewtonBacktracks = 20;  // halvings of a Newton step that inverted an element, a time step
constexpr int kNewtonDetections = 2;   // contact detections a time step

constexpr double kActivationGamma = 0.5;  // γ of the predicted-gap activation rule g + γ h u_n ≤ 0

// Two halves (moreau_jean.h): the margin's travel, as a multiple of the faster of v_k and the last v_θ.
// A step's motion seldom doubles (a start from rest, a velocity through zero): those steps are taken
// again.
constexpr double kReachGrowth = 2.0;

constexpr int kTimerSampling = 16;

// A lumped World keeps its last detection while every moving body's coordinates stay within this
// fraction of a unit of round-off of where it was made (ContactDetector::positions_within), and detects with this
// multiple of the margin the step needs, so that a body at rest, whose margin moves in its last bits
// from step to step, keeps it (see the header).
constexpr double kKeptPoseUlps = 1.0 / 1024.0;
constexpr double kKeptMarginSlack = 2.0;

}  // namespace

MoreauJean::MoreauJean(const World& world, const MoreauJeanParameters& parameters)
    : world_(world),
      parameters_(parameters),
      dynamics_(world),
      operators_(dynamics_),
      pgs_(parameters.solver),
      detector_(world),
      contact_dimension_(detector_.dimension()),
      length_(world.length_scale()),
      ties_(world) {
  two_halves_ = parameters_.two_halves && operators_.sparse() && !operators_.nonlinear() &&
                world_.prescribed.empty() && ties_.empty();
  build_equalities(parameters_.step);
}

// The equality rows C v = target at t (s): the World's linear constraints, then the active prescriptions.
void MoreauJean::build_equalities(double t) {
  dynamics_.equality_rows(t, equalities_);
  ++equalities_built_;
  constraint_columns_.clear();  // A⁻¹ Cᵀ: recomputed for the new rows
}

// The ties' targets at the iterate v_j: with q_j = q_k + h v_θ(v_j), C (v_{k+1} − v_j) = −g(q_j) / (hθ)
// closes the gaps to first order, so that g(q_{k+1}) = 0 at Newton's convergence (the linear scheme,
// one iterate from v_0 = v_k, leaves O(h² |ω|² r) a step, which the next step closes). The rows C are
// taken at the middle of the step, q_k + ½ h v_θ, not at q_j: there C h v_θ is the change of g over
// the step to O(h³) (the chord of a turn seen from its middle), so that the ties' impulses do no work
// (with C(q_j) they would exchange O(h) of the energy over a run); Newton still converges, its
// Jacobian being off by O(h |ω|).
void MoreauJean::linearize_ties(const State& state, const Vector& v_iterate) {
  if (ties_.empty()) return;
  const double h = parameters_.step, theta = parameters_.theta;
  v_theta_ = (1.0 - theta) * state.v + theta * v_iterate;
  integrate_positions(state.q, v_theta_, q_iterate_);
  ties_.compute_gaps(q_iterate_, tie_targets_);
  work_ = 0.5 * v_theta_;
  integrate_positions(state.q, work_, q_tie_rows_);
  ties_.linearize(q_tie_rows_);
  for (int i = 0; i < ties_.size(); ++i)
    tie_targets_(i) = ties_.rows()[i].dot(v_iterate) - tie_targets_(i) / (h * theta);
}

double MoreauJean::equality_dot(int e, const Vector& v) const {
  const int nw = static_cast<int>(equalities_.rows.rows());
  return e < nw ? equalities_.rows.row(e).dot(v) : ties_.rows()[e - nw].dot(v);
}

double MoreauJean::problem_row_dot(int a, const Vector& v) const {
  const int contact_rows = static_cast<int>(rows_.size());
  return a < contact_rows ? rows_[a]->dot(v) : equality_dot(a - contact_rows, v);
}

template <class Dense>
void MoreauJean::add_problem_row(int a, double scale, Dense&& out) const {
  const int contact_rows = static_cast<int>(rows_.size());
  const int ne = static_cast<int>(equalities_.rows.rows());
  if (a < contact_rows) {
    rows_[a]->scatter(scale, out);
  } else if (a < contact_rows + ne) {
    for (int j = 0; j < equalities_.rows.cols(); ++j) out(j) += scale * equalities_.rows(a - contact_rows, j);
  } else {
    ties_.rows()[a - contact_rows - ne].scatter(scale, out);
  }
}

MoreauJean::~MoreauJean() = default;

void MoreauJean::summarize_settings(SummaryEntries& out) const {
  out.add("theta", parameters_.theta).add("close_gaps", parameters_.close_gaps);
}

void MoreauJean::summarize_statistics(const State& state, SummaryEntries& out) const {
  if (state.counters.newton_iterations > 0) add_newton_group(state.counters, parameters_.newton_tolerance, out);
  if (two_halves_) out.add("detections_retaken", state.counters.detections_retaken);
  if (operators_.explicit_inverse() && !detector_.empty()) {
    out.add("detections_kept", state.counters.detections_kept);
    out.add("delassus_kept", state.counters.delassus_kept);
    out.add("contact_solves_repeated", state.counters.solves_repeated);
  }
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
    operators_.sparse_factor().forward_substitute(v_free_, free_forward_, free_scaled_);
    check_free_velocity(free_forward_, state.t + h);
    return;
  }
  operators_.solve_in_place(v_free_);
  v_free_ += state.v;
  check_free_velocity(v_free_, state.t + h);
}

// Newton's free velocity at the iterate v_j: v_free = v_j − A_j⁻¹ R(v_j), with A_j the iteration
// matrix at q_j (refactored here) and
//   R(v_j) = M (v_j − v_k) − h [f_loads + θ f(q_j) + (1−θ) f(q_k) − C v_θ],  v_θ = (1−θ)v_k + θv_j.
// f(q_k) is in f_start_ (computed once a step).
void MoreauJean::compute_newton_free_velocity(const State& state, const Vector& v_iterate) {
  const double h = parameters_.step, theta = parameters_.theta;
  v_theta_ = (1.0 - theta) * state.v + theta * v_iterate;
  integrate_positions(state.q, v_theta_, q_iterate_);
  operators_.update(q_iterate_, h, theta);
  f_iterate_.setZero(state.v.size());
  dynamics_.add_internal_forces(q_iterate_, f_iterate_);
  f_total_ = f_loads_ + theta * f_iterate_ + (1.0 - theta) * f_start_;
  dynamics_.add_damping_force(v_theta_, f_total_);
  dv_ = v_iterate - state.v;
  operators_.apply_mass(dv_, work_);
  v_free_ = h * f_total_ - work_;  // −R(v_j)
  operators_.solve_in_place(v_free_);
  v_free_ += v_iterate;
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
  active_.clear();
  active_rows_.clear();
  if (detector_.empty()) {
    if (two_halves_) gather_candidates();  // the equalities' rows
    return;
  }
  const double h = parameters_.step, theta = parameters_.theta;
  // Broad-phase margin: twice the farthest any point can travel in one step.
  double reach = 0.0, still = std::numeric_limits<double>::infinity();  // still: v_k's travel
  if (two_halves_ && !free_velocity_formed_) {
    // No v_free (see the header): twice the travel of the faster of v_k and the last step's v_θ, which
    // step_in_two_halves checks the step's motion against.
    reach = kReachGrowth * detector_.travel_bound(state.v, h);
    if (v_theta_.size() == state.v.size()) reach = std::max(reach, kReachGrowth * detector_.travel_bound(v_theta_, h));
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
    still = detector_.travel_bound(state.v, h);
    reach = std::max(still, detector_.travel_bound(v_free_, h));
    if (!equalities_.prescriptions.empty()) reach = std::max(reach, detector_.travel_bound(v_predicted_, h));
    if (reach_velocity_.size() > 0) reach = std::max(reach, detector_.travel_bound(reach_velocity_, h));
  }
  const double margin = detection_margin_ = 2.0 * reach + 1e-12;
  if (operators_.explicit_inverse()) {  // a lumped World: the last detection kept, or a new one with slack
    // Only at rest (v_k travels less than the tolerance in a step) is a detection remembered and kept:
    // a moving World's step does none of that bookkeeping.
    at_rest_ = still <= kKeptPoseUlps * std::numeric_limits<double>::epsilon() * length_;
    detection_kept_ = at_rest_ && margin <= kept_margin_ && detector_.positions_within(state.q, kKeptPoseUlps);
    if (!detection_kept_) {
      kept_margin_ = kKeptMarginSlack * margin;
      detector_.detect(state.q, kept_margin_, candidates_, candidate_rows_);
      if (at_rest_) detector_.remember_positions(state.q);
    }
  } else {
    detector_.detect(state.q, margin, candidates_, candidate_rows_);
  }
  if (two_halves_) {  // the rule from the candidates' forward columns (a step taken again too)
    activate_by_forward_columns(state);
    return;
  }
  for (std::size_t k = 0; k < candidates_.size(); ++k) {
    if (kept_margin_ > margin && candidates_[k].point.gap > margin) continue;  // a lumped World's slack
    // The normal velocity the contact would have over a free step (θ-weighted), so that a body at
    // rest under a load that presses it on the surface is caught at the first step, whatever the
    // round-off in its gap. A step taken again over its converged motion (step_newton) also
    // activates what that motion closes.
    const bool closing = closes(k, v_predicted_, kActivationGamma * h) ||
                         (reach_velocity_.size() > 0 && closes(k, reach_velocity_, h));
    if (!closing) continue;
    active_.push_back(candidates_[k]);
    active_rows_.push_back(static_cast<int>(k));
  }
}

// Two halves: every candidate in the Delassus cache, and the rule of step 2 with its free normal
// velocity from its forward column, u_n(v_θ,free) = u_n(v_k) + θ y_nᵀ z (v_θ,free − v_k = θ A⁻¹ h f).
void MoreauJean::activate_by_forward_columns(const State& state) {
  const double h = parameters_.step, theta = parameters_.theta;
  const int d = contact_dimension_;
  gather_candidates();
  for (std::size_t k = 0; k < candidates_.size(); ++k) {
    const double approach = candidate_rows_[d * k].dot(state.v) + theta * candidate_dots_[d * k];
    if (candidates_[k].point.gap + kActivationGamma * h * approach > 0.0) continue;
    active_.push_back(candidates_[k]);
    active_rows_.push_back(static_cast<int>(k));
  }
}

// Whether candidate k's gap closes over `time` at the velocities v: g + time · u_n(v) ≤ 0.
bool MoreauJean::closes(std::size_t k, const Vector& v, double time) const {
  return candidates_[k].point.gap + time * candidate_rows_[contact_dimension_ * k].dot(v) <= 0.0;
}

// The candidates that the converged motion would have activated (detect()'s rule with Newton's v_θ in
// place of the free step's prediction) and the prediction left out: activated now, in candidate order.
int MoreauJean::activate_missed_contacts(double h) {
  std::vector<int> missed;
  std::size_t next_active = 0;
  for (std::size_t k = 0; k < candidates_.size(); ++k) {
    if (next_active < active_rows_.size() && active_rows_[next_active] == static_cast<int>(k)) {
      ++next_active;
      continue;
    }
    if (closes(k, v_theta_, kActivationGamma * h)) missed.push_back(static_cast<int>(k));
  }
  if (missed.empty()) return 0;
  std::vector<int> rows(active_rows_.size() + missed.size());
  std::merge(active_rows_.begin(), active_rows_.end(), missed.begin(), missed.end(), rows.begin());
  active_rows_ = std::move(rows);
  active_.clear();
  for (int k : active_rows_) active_.push_back(candidates_[k]);
  return static_cast<int>(missed.size());
}

// A⁻¹ hᵀ for every row of the problem (a small dense system: a column costs less than a cache look-up).
void MoreauJean::gather_columns() {
  const int n = world_.velocity_size;
  const int d = contact_dimension_;
  const int nc = static_cast<int>(active_.size());
  const int ne = static_cast<int>(equalities_.rows.rows());
  const int nt = ties_.size();
  if (operators_.factorizations() != cache_factorization_) {
    constraint_columns_.clear();
    cache_factorization_ = operators_.factorizations();
  }
  columns_.resize(d * nc + ne + nt);
  direct_columns_.resize(d * nc);
  for (int a = 0; a < d * nc; ++a) {
    direct_columns_[a].setZero(n);
    rows_[a]->scatter(1.0, direct_columns_[a]);
    operators_.solve_in_place(direct_columns_[a]);
    columns_[a] = &direct_columns_[a];
  }
  if (static_cast<int>(constraint_columns_.size()) != ne) {
    constraint_columns_.resize(ne);
    for (int e = 0; e < ne; ++e) {
      constraint_columns_[e] = equalities_.rows.row(e).transpose();
      operators_.solve_in_place(constraint_columns_[e]);
    }
  }
  for (int e = 0; e < ne; ++e) columns_[d * nc + e] = &constraint_columns_[e];
  tie_columns_.resize(nt);  // new rows at every iterate
  for (int i = 0; i < nt; ++i) {
    tie_columns_[i].setZero(n);
    ties_.rows()[i].scatter(1.0, tie_columns_[i]);
    operators_.solve_in_place(tie_columns_[i]);
    columns_[d * nc + ne + i] = &tie_columns_[i];
  }
}

// A lumped World keeps A⁻¹ (structural_operators.h): G = A⁻¹ Hᵀ and W = H G, symmetric, are small
// products (small_dense_products.h), with Hᵀ's columns the problem's rows. No solve.
void MoreauJean::dense_delassus() {
  // Kept with the detection, for the same active contacts, equality rows and A⁻¹ (see the header).
  delassus_kept_ = detection_kept_ && delassus_rows_ == active_rows_ &&
                  delassus_factorization_ == operators_.factorizations() && delassus_equalities_ == equalities_built_;
  if (delassus_kept_) return;
  const int m = static_cast<int>(rows_.size()) + equality_count();
  fresh_columns_.setZero(world_.velocity_size, m);  // Hᵀ
  const int contact_rows = static_cast<int>(rows_.size());
  for (int a = 0; a < contact_rows; ++a) {  // a contact row's distinct entries: scatter's 0 + 1·x, written
    const SparseRow& row = *rows_[a];
    double* column = fresh_columns_.col(a).data();
    for (int k = 0; k < row.count; ++k) column[row.index[k]] = 0.0 + row.value[k];
  }
  for (int a = contact_rows; a < m; ++a) add_problem_row(a, 1.0, fresh_columns_.col(a));
  // Also kept for Hᵀ the same to the bit with the same A⁻¹ (a box sliding without turning): W and
  // G = A⁻¹ Hᵀ are functions of them.
  delassus_kept_ = delassus_factorization_ == operators_.factorizations() &&
                   fresh_columns_.cols() == problem_columns_.cols() && fresh_columns_.rows() == problem_columns_.rows() &&
                   same_bits(fresh_columns_.data(), problem_columns_.data(), static_cast<std::size_t>(fresh_columns_.size()));
  if (at_rest_) {  // what the next steps compare, if they keep the detection (only at rest)
    delassus_rows_ = active_rows_;
    delassus_equalities_ = equalities_built_;
  }
  if (delassus_kept_) return;
  ++delassus_formed_;
  delassus_factorization_ = operators_.factorizations();
  problem_columns_.swap(fresh_columns_);
  operators_.dense_columns(problem_columns_, dense_columns_);
  small_symmetric_gram(problem_columns_, dense_columns_, problem_.W);
}

// A sparse linear World: every row of the problem in the Delassus cache, its slot in delassus_slots_.
void MoreauJean::gather_delassus() {
  const int d = contact_dimension_;
  const int nc = static_cast<int>(active_.size());
  const int ne = static_cast<int>(equalities_.rows.rows());
  delassus_slots_.resize(d * nc + equality_count());
  delassus_cache_.begin(operators_.sparse_factor());
  for (int i = 0; i < nc; ++i)
    for (int k = 0; k < d; ++k) {
      const SparseRow& row = *rows_[d * i + k];
      delassus_slots_[d * i + k] =
          delassus_cache_.slot({0, active_[i].point.key, k}, row.index.data(), row.value.data(), row.count);
    }
  for (int e = 0; e < ne; ++e) delassus_slots_[d * nc + e] = equality_slot(e);
  for (int i = 0; i < ties_.size(); ++i) {
    const SparseRow& row = ties_.rows()[i];
    delassus_slots_[d * nc + ne + i] = delassus_cache_.slot({2, {}, i}, row.index.data(), row.value.data(), row.count);
  }
  delassus_cache_.finish();
}

int MoreauJean::equality_slot(int e) {
  equality_index_.clear();
  equality_value_.clear();
  for (int j = 0; j < world_.velocity_size; ++j)
    if (equalities_.rows(e, j) != 0.0) {
      equality_index_.push_back(j);
      equality_value_.push_back(equalities_.rows(e, j));
    }
  return delassus_cache_.slot({1, {}, e}, equality_index_.data(), equality_value_.data(),
                              static_cast<int>(equality_index_.size()));
}

// Two halves: the rows of every candidate, then of the equalities (no ties), in the Delassus cache; a
// candidate that is not activated keeps its forward column for the next step's rule.
void MoreauJean::gather_candidates() {
  const int d = contact_dimension_;
  const int candidates = static_cast<int>(candidates_.size());
  const int ne = static_cast<int>(equalities_.rows.rows());
  candidate_slots_.resize(d * candidates + ne);
  delassus_cache_.begin(operators_.sparse_factor());
  for (int i = 0; i < candidates; ++i)
    for (int k = 0; k < d; ++k) {
      const SparseRow& row = candidate_rows_[d * i + k];
      candidate_slots_[d * i + k] =
          delassus_cache_.slot({0, candidates_[i].point.key, k}, row.index.data(), row.value.data(), row.count);
    }
  for (int e = 0; e < ne; ++e) candidate_slots_[d * candidates + e] = equality_slot(e);
  delassus_cache_.finish();
  forward_rows_.assign(delassus_cache_, candidate_slots_, operators_.sparse_factor().size());
  forward_rows_.dots(free_scaled_, candidate_dots_);
}

// Two halves: the candidate row (in candidate_slots_' order) of the problem's row a: an active contact's
// rows are its candidate's, the equalities' come after every candidate's.
int MoreauJean::candidate_row(int a) const {
  const int d = contact_dimension_;
  const int nc = static_cast<int>(active_.size());
  return a < d * nc ? d * active_rows_[a / d] + a % d : d * static_cast<int>(candidates_.size()) + (a - d * nc);
}

void MoreauJean::assemble(const State& state) {
  const int d = contact_dimension_;
  const int nc = static_cast<int>(active_.size());
  const int ne = static_cast<int>(equalities_.rows.rows());
  const int nw = static_cast<int>(world_.constraints.size());
  const int m = d * nc + equality_count();
  const double h = parameters_.step, theta = parameters_.theta;

  problem_.dimension = d;
  problem_.contacts = nc;
  problem_.equalities = equality_count();
  problem_.mu.resize(nc);
  rows_.resize(d * nc);
  for (int i = 0; i < nc; ++i) {
    for (int k = 0; k < d; ++k) rows_[d * i + k] = &candidate_rows_[d * active_rows_[i] + k];
    problem_.mu[i] = world_.contact_laws[active_[i].law].mu_at(state.t + h);
  }
  problem_.W.resize(m, m);
  problem_.b.resize(m);
  if (operators_.direct_delassus()) {  // no columns: update() takes one solve with Hᵀ r
    problem_rows_.setZero(m, world_.velocity_size);
    for (int a = 0; a < m; ++a) add_problem_row(a, 1.0, problem_rows_.row(a));
    operators_.delassus(problem_rows_, problem_.W);
  } else if (operators_.explicit_inverse()) {
    dense_delassus();
  } else if (operators_.sparse()) {
    if (two_halves_) {  // the active candidates' slots, then the equalities' (gathered by detect)
      delassus_slots_.resize(m);
      for (int i = 0; i < nc; ++i)
        for (int k = 0; k < d; ++k) delassus_slots_[d * i + k] = candidate_slots_[d * active_rows_[i] + k];
      const int first_equality = d * static_cast<int>(candidates_.size());
      for (int e = 0; e < ne; ++e) delassus_slots_[d * nc + e] = candidate_slots_[first_equality + e];
    } else {
      gather_delassus();
    }
    if (!delassus_cache_.still_holds(copied_, delassus_slots_)) {
      for (int a = 0; a < m; ++a)
        for (int b = 0; b < m; ++b) problem_.W(a, b) = delassus_cache_(delassus_slots_[a], delassus_slots_[b]);
    }
  } else {
    gather_columns();
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b) problem_.W(a, b) = problem_row_dot(a, *columns_[b]);
  }
  // A lumped World has the rows as Hᵀ's dense columns (dense_delassus): b = H v_free by dense dots of
  // n entries, a few instructions each at the compiled sizes (the sparse rows' dots cost about five
  // an entry; the sums differ in their order, so in their last bits).
  const bool dense_rows = operators_.explicit_inverse();
  if (dense_rows) {
    small_transpose_multiply(problem_columns_, v_free_, problem_.b);
  } else if (two_halves_) {  // H v_free = H v_k + Yᵀ z (see the header), Yᵀ z from detect
    for (int a = 0; a < m; ++a) problem_.b(a) = problem_row_dot(a, state.v) + candidate_dots_[candidate_row(a)];
  } else {
    for (int a = 0; a < m; ++a) problem_.b(a) = problem_row_dot(a, v_free_);
  }
  for (int i = 0; i < nc; ++i) {
    const double e = world_.contact_laws[active_[i].law].restitution;
    const double approach = dense_rows ? small_column_dot(problem_columns_, d * i, state.v) : rows_[d * i]->dot(state.v);
    if (e > 0.0) {
      problem_.b(d * i) += e * approach;
    } else if (parameters_.close_gaps) {
      // An inelastic contact still open by g: its condition is g(q_{k+1}) ≥ 0, that is
      // u_n(v_{k+1}) ≥ −(g + h(1−θ) u_n(v_k)) / (hθ), so that it closes the gap within the step and
      // stops on the surface, not wherever the activation rule caught it (header, step 3).
      const double opening = active_[i].point.gap + h * (1.0 - theta) * approach;
      if (opening > 0.0) problem_.b(d * i) += opening / (h * theta);
    }
  }
  // Equality targets: C v_{k+1} such that C (q_{k+1} − q_ref) = value exactly (a prescription's
  // value at t_{k+1}).
  for (int e = 0; e < ne; ++e) {
    const double value = e >= nw ? world_.prescribed[equalities_.prescriptions[e - nw]].value(state.t + h)
                                 : world_.constraints[e].value;
    double target = 0.0;
    bool position_level = true;
    double displacement = 0.0;
    for (const auto& [p, coefficient] : equalities_.terms[e]) {
      if (p < 0) { position_level = false; break; }
      double reference = 0.0;
      for (const BodyInstance& b : world_.bodies)
        if (p >= b.position_offset && p < b.position_offset + b.body->position_size())
          reference = b.reference_position(p - b.position_offset);
      displacement += coefficient * (state.q(p) - reference);
    }
    const double rate_k = equalities_.rows.row(e).dot(state.v);
    if (position_level) {
      target = (value - displacement - h * (1.0 - theta) * rate_k) / (h * theta);
    } else if (e >= nw) {  // a 3D rigid body's rotation: prescribed through its rate over the step
      const double rate = (value - world_.prescribed[equalities_.prescriptions[e - nw]].value(state.t)) / h;
      target = (rate - (1.0 - theta) * rate_k) / theta;
    }
    problem_.b(d * nc + e) -= target;
  }
  for (int i = 0; i < ties_.size(); ++i) problem_.b(d * nc + ne + i) -= tie_targets_(i);
}

void MoreauJean::solve(State& state, bool warm_from_state) {
  // Newton's later iterations start from the last iteration's r_ (same contacts, same order).
  if (warm_from_state || r_.size() != problem_.size())
    warm_start(state.contacts, active_, contact_dimension_, problem_.size(), r_);
  const double t_next = state.t + parameters_.step;
  // A lumped World's problem the same to the bit as the last kept one (the same W, b, μ and warm start)
  // has its solution: the solve is a function of them (see the header). Only at rest: a moving World's
  // b differs at every step, and its W is kept only while the rows stay the same to the bit.
  KeptSolve& kept = kept_solve_;
  const bool repeatable = delassus_kept_ && at_rest_;
  if (repeatable && kept.delassus == delassus_formed_ && problem_.size() > 0 && kept.b.size() == problem_.b.size() &&
      kept.mu.size() == problem_.mu.size() && same_bits(kept.b.data(), problem_.b.data(), kept.b.size()) &&
      same_bits(reinterpret_cast<const double*>(kept.mu.data()), reinterpret_cast<const double*>(problem_.mu.data()),
                2 * kept.mu.size()) &&
      same_bits(kept.warm.data(), r_.data(), kept.warm.size())) {
    r_ = kept.r;
    statuses_ = kept.status;
    ++state.counters.solves_repeated;
    if (const std::string failure = account_contact_solve(kept.statistics, contact_dimension_, parameters_.failure_residual,
                                                          t_next, r_, statuses_, active_, state.counters);
        !failure.empty())
      throw RunError(t_next, failure);
    return;
  }
  if (repeatable) {
    kept.delassus = delassus_formed_;
    kept.b = problem_.b;
    kept.mu = problem_.mu;
    kept.warm = r_;
  }
  if (const std::string failure =
          solve_contacts(pgs_, problem_, parameters_.failure_residual, t_next, r_, active_, state.counters,
                         &statuses_, &kept.statistics);
      !failure.empty())
    throw RunError(t_next, failure);
  if (repeatable) {  // (a W formed since has another count: delassus_formed_ moved on)
    kept.r = r_;
    kept.status = statuses_;
  }
}

void MoreauJean::update(State& state) {
  const double theta = parameters_.theta;
  const int rows = static_cast<int>(r_.size());
  if (two_halves_) {  // v_k + Pᵀ L⁻ᵀ D⁻¹ (w + Y r): the backward half (see the header)
    forward_sum_ = free_forward_;
    candidate_impulses_.assign(forward_rows_.columns(), 0.0);
    candidate_in_problem_.assign(forward_rows_.columns(), 0);
    for (int a = 0; a < rows; ++a) {
      const int c = candidate_row(a);
      candidate_impulses_[c] = r_(a);
      candidate_in_problem_[c] = 1;
    }
    forward_rows_.add(candidate_impulses_, candidate_in_problem_, forward_sum_);
    operators_.sparse_factor().back_substitute(forward_sum_, work_);
    v_next_ = state.v + work_;
  } else {
    v_next_ = v_free_;
    if (rows > 0 && operators_.sparse() && !operators_.direct_delassus()) {
      // A⁻¹ Hᵀ r = Pᵀ L⁻ᵀ D⁻¹ (Y r): the forward columns kept for W, then a backward substitution alone.
      const SparseLdlt& factor = operators_.sparse_factor();
      forward_sum_.setZero(factor.size());
      for (int a = 0; a < rows; ++a) SparseLdlt::add_scaled(r_(a), delassus_cache_.forward(delassus_slots_[a]), forward_sum_);
      factor.back_substitute(forward_sum_, work_);
      v_next_ += work_;
    } else if (rows > 0 && operators_.sparse()) {
      // One solve A⁻¹ (Hᵀ r) costs less than the sum of the columns when the system is large.
      work_.setZero(world_.velocity_size);
      for (int a = 0; a < rows; ++a) add_problem_row(a, r_(a), work_);
      operators_.solve_in_place(work_);
      v_next_ += work_;
    } else if (operators_.explicit_inverse()) {
      // G r column by column, in the rows' order: a resting contact's velocity then cancels exactly, as
      // with the factored path's columns.
      small_add_columns(dense_columns_, r_, v_next_);
    } else {
      for (int a = 0; a < rows; ++a) v_next_ += r_(a) * *columns_[a];
    }
  }
  v_theta_ = (1.0 - theta) * state.v + theta * v_next_;
  integrate_positions(state.q, v_theta_, q_next_);
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
  if (operators_.explicit_inverse()) {  // H v_θ by Hᵀ's dense columns, as b in assemble()
    for (int a = 0; a < static_cast<int>(r_.size()); ++a)
      e.contact_dissipation -= r_(a) * small_column_dot(problem_columns_, a, v_theta_);
  } else {
    for (int a = 0; a < static_cast<int>(r_.size()); ++a) e.contact_dissipation -= r_(a) * problem_row_dot(a, v_theta_);
  }
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

// One step with finite-strain bodies: Newton on v_{k+1}, the contact solve inside (see the header).
// The contacts are detected at its first iteration, within a margin of the motion predicted then; a
// converged step that moved a point farther than that margin is taken again, detected over its own
// motion (at most kNewtonDetections detections).
void MoreauJean::step_newton(State& state) {
  const double h = parameters_.step;
  compute_loads(state);
  f_start_.setZero(state.v.size());
  dynamics_.add_internal_forces(state.q, f_start_);
  SolverCounters& c = state.counters;
  reach_velocity_.resize(0);
  int iterations = 0;
  for (int detections = 1;; ++detections) {
    iterations += newton_iterations(state);
    const double travel = detector_.empty() ? 0.0 : detector_.travel_bound(v_theta_, h);
    if (travel <= detection_margin_) break;
    if (detections == kNewtonDetections) {
      std::ostringstream message;
      message << "moreau-jean: Newton's step at t = " << state.t + h << " s moves a point by " << travel
              << " m, farther than its contact detection reached (" << detection_margin_ << " m) after "
              << detections << " detections (a smaller time.step)";
      throw RunError(state.t + h, message.str());
    }
    ++c.newton_redetections;
    reach_velocity_ = v_theta_;
  }
  c.newton_iterations += iterations;
  c.max_newton_iterations = std::max(c.max_newton_iterations, iterations);
  c.newton_regularized = operators_.regularizations();
}

// Newton's iterations from v_k to convergence, the contacts detected at the first; returns how many.
// Along the way (secant_relaxation.h) a step may be lengthened or shortened by its secant model; a step
// after which an element inverts is halved (at most kNewtonBacktracks times a step); at convergence,
// the candidates that its motion would have activated and the prediction did not are activated and the
// iterations go on (they would otherwise cross the surface unseen within the step).
int MoreauJean::newton_iterations(State& state) {
  const double h = parameters_.step;
  SolverCounters& c = state.counters;
  v_iterate_ = state.v;
  relaxation_.reset();
  double relaxation = 1.0;  // the last step's ω
  int backtracks = 0;
  for (int iteration = 1;; ++iteration) {
    try {
      compute_newton_free_velocity(state, v_iterate_);
    } catch (const FemError& e) {
      if (iteration > 1 && backtracks < kNewtonBacktracks) {  // the last step inverted an element: shorten it
        const double shorter = relaxation > 1.0 ? 1.0 : 0.5 * relaxation;
        v_iterate_ -= (relaxation - shorter) * newton_step_;
        relaxation = shorter;
        relaxation_.reset();
        ++backtracks;
        ++c.newton_backtracks;
        --iteration;
        continue;
      }
      throw RunError(state.t + h, "moreau-jean Newton iteration " + std::to_string(iteration) + ": " + e.what());
    }
    clock_.lap(state.timers.free_velocity);
    if (iteration == 1) detect(state);
    clock_.lap(state.timers.detection);
    linearize_ties(state, v_iterate_);
    assemble(state);
    clock_.lap(state.timers.assembly);
    solve(state, iteration == 1);
    clock_.lap(state.timers.solve);
    update(state);
    clock_.lap(state.timers.update);
    newton_step_ = v_next_ - v_iterate_;
    const double increment = h * newton_step_.lpNorm<Eigen::Infinity>();
    relaxation = 1.0;
    if (increment <= parameters_.newton_tolerance * length_) {
      const int missed = activate_missed_contacts(h);
      if (missed == 0) return iteration;
      c.newton_activated_contacts += missed;
      relaxation_.reset();
    } else if (iteration >= parameters_.newton_max_iterations || !std::isfinite(increment)) {
      std::ostringstream message;
      message << "moreau-jean: Newton did not converge at t = " << state.t + h << " s: h|dv| = " << increment
              << " after " << iteration << " iterations (tolerance " << parameters_.newton_tolerance * length_
              << "; integrator.newton_max_iterations, or a smaller time.step)";
      throw RunError(state.t + h, message.str());
    } else {
      relaxation = relaxation_.next(newton_step_);
    }
    if (relaxation == 1.0) {
      v_iterate_ = v_next_;  // exactly, not v_j + (v_{j+1} − v_j)
    } else {
      ++c.newton_relaxed;
      v_iterate_ += relaxation * newton_step_;
    }
  }
}

// Steps 2 to 5 of a linear step, each phase timed.
void MoreauJean::detect_solve_update(State& state) {
  detect(state);
  clock_.lap(state.timers.detection);
  linearize_ties(state, state.v);
  assemble(state);
  clock_.lap(state.timers.assembly);
  solve(state);
  clock_.lap(state.timers.solve);
  update(state);
}

// Two halves (see the header), after the forward half: detection, contact solve and the backward half
// without v_free; taken again with v_free formed if the step's motion went farther than the margin
// covered (the counters of the first solve are then dropped).
void MoreauJean::step_in_two_halves(State& state) {
  const double h = parameters_.step;
  const SolverCounters counted = state.counters;
  free_velocity_formed_ = false;
  detect_solve_update(state);
  if (detector_.empty() || detector_.travel_bound(v_theta_, h) <= reach_) return;
  state.counters = counted;
  ++state.counters.detections_retaken;
  operators_.sparse_factor().back_substitute(free_forward_, v_free_);
  v_free_ += state.v;
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
    step_newton(state);  // laps each phase of each iteration
    state.factorization_seconds = operators_.factorization_seconds();
  } else {
    compute_free_velocity(state);
    state.factorization_seconds = operators_.factorization_seconds();
    clock_.lap(state.timers.free_velocity);
    if (two_halves_) step_in_two_halves(state);
    else detect_solve_update(state);
    if (detection_kept_) ++state.counters.detections_kept;
    if (delassus_kept_ && problem_.size() > 0) ++state.counters.delassus_kept;
  }
  account_energy(state);
  if (!v_next_.allFinite() || !q_next_.allFinite()) {
    std::ostringstream message;
    message << "non-finite state at t = " << state.t + parameters_.step
            << " s (check the time step, stiffness and loads)";
    throw RunError(state.t + parameters_.step, message.str());
  }
  if (!world_.prescribed.empty()) {  // the force each prescription exerted: its impulse / h
    state.reactions.setZero(world_.velocity_size);
    const int first = static_cast<int>(rows_.size() + world_.constraints.size());
    for (std::size_t i = 0; i < equalities_.prescriptions.size(); ++i) {
      const PrescribedComponent& p = world_.prescribed[equalities_.prescriptions[i]];
      state.reactions(world_.bodies[p.body].velocity_offset + p.component) = r_(first + i) / parameters_.step;
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
  state.t = static_cast<double>(c.steps) * parameters_.step;  // no accumulated round-off
  state.contacts.swap(active_);
  c.contact_points += static_cast<long>(state.contacts.size());
  c.max_contact_points = std::max(c.max_contact_points, static_cast<int>(state.contacts.size()));
  clock_.lap(state.timers.update);
}

}  // namespace csim
