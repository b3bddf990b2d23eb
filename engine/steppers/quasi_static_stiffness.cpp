// QuasiStatic's holding of the stiffness positive definite (quasi_static.h, "Holding K_z positive
// definite" and "Soft directions"): the held rows, the proximal terms, the soft directions' terms, and the
// check that the accepted iterate's contacts hold what the proximal terms held.
#include "engine/steppers/quasi_static.h"

#include "engine/linear_algebra/sparse_assembly.h"
#include "engine/steppers/proximal.h"

#include <algorithm>
#include <sstream>

namespace csim {

namespace {

constexpr double kSoftProximal = 1e-6;  // ε / K_jj on a soft direction's unknown
constexpr int kSoftRounds = 8;          // refactorizations that may find further such directions

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

}  // namespace

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

// scale · h_aᵀ h_a, h_a row a of H_z, into triplets (the held rows' ρ H_Aᵀ H_A).
void QuasiStatic::add_row_product(int a, double scale, Triplets& triplets) {
  const Matrix& H = operator_->reduced_rows();
  row_unknowns_.clear();
  for (int k = 0; k < H.cols(); ++k)
    if (H(a, k) != 0.0) row_unknowns_.push_back(k);
  for (int k : row_unknowns_)
    for (int l : row_unknowns_) triplets.emplace_back(k, l, scale * H(a, k) * H(a, l));
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

// The soft directions' unknowns, named (at most three), for messages.
std::string QuasiStatic::soft_directions() const {
  std::ostringstream names;
  for (std::size_t k = 0; k < soft_unknowns_.size() && k < 3; ++k)
    names << (k > 0 ? ", " : "") << describe_unknown(soft_unknowns_[k]);
  if (soft_unknowns_.size() > 3) names << " and " << soft_unknowns_.size() - 3 << " more";
  return names.str();
}

}  // namespace csim
