// Moreau–Jean's equality rows (moreau_jean.h, step 3): the targets that make the linear constraints and
// prescribed components hold in position at t_{k+1}, and the ties' rows linearized at each iterate.
#include "engine/steppers/moreau_jean.h"

namespace csim {

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

// Equality e's target: C v_{k+1} such that C (q_{k+1} − q_ref) = value exactly (a prescription's value
// at t_{k+1}).
double MoreauJean::equality_target(const State& state, int e) const {
  const double h = parameters_.step, theta = parameters_.theta;
  const int nw = static_cast<int>(world_.constraints.size());
  const double value = e >= nw ? world_.prescribed[equalities_.prescriptions[e - nw]].value(state.t + h)
                               : world_.constraints[e].value;
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
  if (position_level) return (value - displacement - h * (1.0 - theta) * rate_k) / (h * theta);
  if (e < nw) return 0.0;
  // A 3D rigid body's rotation: prescribed through its rate over the step.
  const double rate = (value - world_.prescribed[equalities_.prescriptions[e - nw]].value(state.t)) / h;
  return (rate - (1.0 - theta) * rate_k) / theta;
}

}  // namespace csim
