// The contact stage of a time step, the same for every stepper (Siconos' OneStepNSProblem / LinearOSNS,
// Drake's contact_solvers): detect → the rows H → W = H A⁻¹ Hᵀ and b → solve → A⁻¹ Hᵀ r. Moreau–Jean and
// generalized-α at the velocity level; the quasi-static stepper at the position level, its rows mapped to
// its reduced unknowns by its operator (quasi_static_operator.h), its b its own, and several solves over
// one detection (warm_start_from, solve_from_impulses).
//
//   detect        ContactDetector (contact_detector.h): candidates within a margin (m) at q, sorted by
//                 key, each with its d rows of H (normal, then tangents; d = 2 in plane scenes, 3 in
//                 space); the stepper activates those its rule closes (a predicted gap ≤ touching());
//   rows          the active contacts' rows, then the stepper's equality rows (linear constraints,
//                 prescriptions) and ties (problem_rows.h); μ of each contact at t_{k+1};
//   W             the Delassus operator H A⁻¹ Hᵀ, formed in one place (form_delassus) by the stepper's
//                 iteration matrix (iteration_operator.h), which alone knows how A⁻¹ is stored;
//   b             H v_free (free_term), to which the stepper adds its impact law, gap closing and the
//                 equality targets: the problem u = W r + b of contact/friction_contact_problem.h;
//   solve         warm start from the last step's impulses with the same key, projected Gauss–Seidel with
//                 exact local solves (contact/pgs_solver.h); a solve left above failure_residual stops
//                 the run (RunError);
//   response      v += A⁻¹ Hᵀ r (add_response).
// Units: impulses r in N·s, velocities in m/s (rad/s on rotations), gaps and margins in m, gap positive
// when open, the normal from body A to body B.
#pragma once

#include "contact/pgs_solver.h"
#include "engine/contact_stage/contact_detector.h"
#include "engine/contact_stage/iteration_operator.h"
#include "engine/state.h"

#include <memory>
#include <string>
#include <vector>

namespace csim {

class ContactStage {
 public:
  ContactStage(const World& world, const PgsParameters& solver, std::unique_ptr<IterationOperator> iteration);

  bool empty() const { return detector_.empty(); }  // no body can touch another
  int dimension() const { return dimension_; }
  const ContactDetector& detector() const { return detector_; }
  void set_asleep(const std::vector<char>* asleep) { detector_.set_asleep(asleep); }  // ContactDetector's

  // Candidates with gap ≤ margin + touching() (m) at q; none active yet.
  void detect(const Vector& q, double margin);
  // The gap (m) below which a contact counts as closed: kTouching × World::length_scale (the largest
  // moving body's bounding radius). Bodies resting on each other touch at a gap of round-off, and at
  // rest a contact solved to a tolerance drifts open by about tolerance × h × the velocity scale a step;
  // with "closed" meaning gap ≤ 0 such contacts leave and re-enter the problem from step to step. In a
  // packed pile (bench/pile_scene.h) the sideways contacts that hold the stack then drop out and the
  // spheres move (100 spheres: 296 of the 390 touching pairs left after 10 steps, each solve a new
  // problem for the warm start; with the band all 390 stay). Moreau–Jean's gap
  // closing (moreau_jean.h step 3) reads a gap within the band as 0, so such a contact may stay open by
  // up to the band. Generalized-α closes it: its velocity-level condition does not hold its positions,
  // and without the closing the elastic shoe at ρ∞ = 0.95 rings 40 times more (generalized_alpha_test.cpp).
  double touching() const { return touching_; }
  static constexpr double kTouching = 1e-9;  // dimensionless, of the World's length scale
  int candidate_count() const { return static_cast<int>(candidates_.size()); }
  const std::vector<ActiveContact>& candidates() const { return candidates_; }
  const std::vector<SparseRow>& candidate_rows() const { return candidate_rows_; }  // d a candidate
  // Candidate k's gap after `time` (s) at velocities v: g + time · u_n(v) (m).
  double predicted_gap(int k, const Vector& v, double time) const {
    return candidates_[k].point.gap + time * candidate_rows_[dimension_ * k].dot(v);
  }
  void activate(int k);  // in increasing k
  bool is_active(int k) const;
  // Activates these candidates too (not active yet, increasing k), keeping the candidates' order.
  void activate_more(const std::vector<int>& more);
  const std::vector<ActiveContact>& active() const { return active_; }

  // The rows of the problem: the active contacts', then these equalities (ne × n, or none) and ties;
  // μ at t (s).
  void gather_rows(const Matrix* equalities, const std::vector<SparseRow>* ties, double t);
  const ProblemRows& rows() const { return rows_; }
  // W in problem(): as the choice says (iteration_operator.h; automatic unless set), dense where the
  // operator cannot store it sparse.
  // dense: W stored dense and solved on the dense path (PgsParameters::route_sparse off).
  void set_delassus_choice(DelassusChoice choice) {
    choice_ = choice;
    PgsParameters parameters = pgs_.parameters();
    parameters.route_sparse = choice != DelassusChoice::dense;
    pgs_ = PgsSolver(parameters);
  }
  void form_delassus();
  // b = H v_free, after form_delassus (an operator may apply the H it formed W with).
  void free_term(const Vector& v_free) { iteration_->apply_rows(rows_, v_free, problem_.b); }
  FrictionContactProblem& problem() { return problem_; }

  // Solves with the warm start from `previous` (the last step's contacts) or, when warm_from_previous is
  // false and the problem kept its size, from the last impulses; accounts in `counters`.
  void solve(const std::vector<ActiveContact>& previous, bool warm_from_previous, double failure_residual,
             double t_next, SolverCounters& counters);
  // The same solve in two parts, for a stepper that solves several times over one detection (the
  // quasi-static stepper's Newton iterates and their passes): r from `previous`' impulses of the same key
  // (statuses, when given, get their statuses, open for a new contact); then a solve from r as it stands,
  // which returns the failure message instead of throwing it (an iterate the stepper does not accept may
  // fail).
  void warm_start_from(const std::vector<ActiveContact>& previous, std::vector<ContactStatus>* statuses = nullptr);
  [[nodiscard]] std::string solve_from_impulses(double failure_residual, double t_next, SolverCounters& counters);
  const Vector& impulses() const { return r_; }
  void add_response(Vector& v) { iteration_->add_response(rows_, r_, v); }  // v += A⁻¹ Hᵀ r
  // rᵀ H v (J, for v in m/s: the impulses' work over a step at the velocities v).
  double impulse_work(const Vector& v) {
    iteration_->apply_rows(rows_, v, velocities_);
    return r_.dot(velocities_);
  }
  // The active contacts with their impulses and statuses, for State::contacts (swapped out: the stage's
  // list is then the caller's old one, cleared at the next detection).
  void hand_over(std::vector<ActiveContact>& contacts) { contacts.swap(active_); }

 private:
  const World& world_;
  double touching_ = 0.0;  // m (touching())
  ContactDetector detector_;
  int dimension_;
  PgsSolver pgs_;
  std::unique_ptr<IterationOperator> iteration_;
  DelassusChoice choice_ = DelassusChoice::automatic;
  std::vector<ActiveContact> candidates_, active_;
  std::vector<SparseRow> candidate_rows_;
  std::vector<int> active_candidates_;  // increasing
  ProblemRows rows_;
  FrictionContactProblem problem_;
  Vector r_, velocities_;
  std::vector<ContactStatus> statuses_;
};

}  // namespace csim
