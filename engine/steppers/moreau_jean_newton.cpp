// Moreau–Jean with finite-strain bodies: the step as a Newton loop on v_{k+1} with the contact problem
// inside every iteration (moreau_jean.h).
#include "engine/steppers/moreau_jean.h"

#include "fem/mesh.h"

#include <cmath>
#include <sstream>

namespace csim {

namespace {

constexpr int kNewtonBacktracks = 20;  // halvings of a Newton step that inverted an element, a time step
constexpr int kNewtonDetections = 2;   // contact detections a time step

}  // namespace

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
    const double travel = stage_.empty() ? 0.0 : stage_.detector().travel_bound(v_theta_, h);
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
    // Newton's later iterations start from the last iteration's impulses (same contacts, same order).
    stage_.solve(state.contacts, iteration == 1, parameters_.failure_residual, state.t + h, state.counters);
    clock_.lap(state.timers.solve);
    update(state);
    clock_.lap(state.timers.update);
    newton_step_ = v_next_ - v_iterate_;
    const double increment = h * newton_step_.lpNorm<Eigen::Infinity>();
    relaxation = 1.0;
    if (increment <= parameters_.newton_tolerance * length_) {
      // The candidates that the converged motion would have activated (detect()'s rule with Newton's
      // v_θ in place of the free step's prediction) and the prediction left out.
      const int missed = activate_closed_by_motion(kActivationGamma * h);
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

}  // namespace csim
