#include "engine/steppers/ida_integrator.h"

#include "engine/steppers/event_contact_model.h"
#include "engine/steppers/integrator.h"
#include "engine/steppers/regularized_contact_model.h"

#include <ida/ida.h>
#include <ida/ida_ls.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace csim {

namespace {

constexpr int kDenseLimit = 100;  // unknowns up to which the dense solver is chosen automatically

int residual_callback(realtype t, N_Vector y, N_Vector yp, N_Vector r, void* user) {
  return static_cast<IdaIntegrator*>(user)->residual(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp),
                                                     N_VGetArrayPointer(r));
}

int jacobian_callback(realtype t, realtype cj, N_Vector y, N_Vector yp, N_Vector, SUNMatrix J, void* user,
                      N_Vector, N_Vector, N_Vector) {
  return static_cast<IdaIntegrator*>(user)->sparse_jacobian(t, cj, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), J);
}

int event_callback(realtype t, N_Vector y, N_Vector yp, realtype* g, void* user) {
  return static_cast<IdaIntegrator*>(user)->event_functions(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), g);
}

void error_callback(int code, const char* module, const char* function, char* message, void* user) {
  std::ostringstream text;
  text << function << ": " << message;
  static_cast<IdaIntegrator*>(user)->record_error(text.str());
}

}  // namespace

struct IdaIntegrator::Sundials {
  SUNContext context = nullptr;
  void* memory = nullptr;
  N_Vector y = nullptr, y_rate = nullptr;
  SUNMatrix matrix = nullptr;
  SUNLinearSolver solver = nullptr;
  bool sparse = false;
  ~Sundials() {
    if (memory) IDAFree(&memory);
    if (solver) SUNLinSolFree(solver);
    if (matrix) SUNMatDestroy(matrix);
    if (y) N_VDestroy(y);
    if (y_rate) N_VDestroy(y_rate);
    if (context) SUNContext_Free(&context);
  }
};

std::string IdaIntegrator::unsupported(const World& world, const IdaParameters& parameters) {
  const std::string name = integrator_name(parameters.events ? Integrator::ida_events : Integrator::ida);
  if (!world.prescribed.empty())
    return name + " does not take prescribed motions (a body's 'prescribed' components); use moreau-jean or quasi-static";
  if (!world.ties.empty())
    return name + " does not take elastic bodies tied to rigid ones ('tied_to'); use moreau-jean or quasi-static";
  for (const ContactLaw& law : world.contact_laws)
    if (!law.between_bodies())  // the penalty and the event models are set per pair of bodies
      return name + " takes contact laws between two bodies (contact law '" + law.name +
             "' names a group); use moreau-jean";
  // A triangle mesh's contacts change point and normal from one triangle to the next, a jump the
  // smooth integrator's error control resolves by collapsing its step: terrain-mesh under ida did not
  // finish 0.01 s in 5 minutes.
  for (const BodyInstance& b : world.bodies)
    for (const ShapeInstance& shape : b.shapes)
      if (std::holds_alternative<TriangleMesh>(shape.shape))
        return name + " does not take triangle meshes (body '" + b.name + "', shape '" + shape.name +
               "'): the contacts' jumps from triangle to triangle stall its step control; use moreau-jean";
  for (const ContactLaw& law : world.contact_laws)
    if (!law.collides)
      return name + " sets its contacts by law; it does not take a law whose pairs never collide (contact law '" +
             law.name + "': collide: false); use moreau-jean";
  for (const ContactLaw& law : world.contact_laws)
    if (law.mu_ramp_end > law.mu_ramp_start)
      return name + " does not take a friction ramp (contact law '" + law.name + "' has mu_ramp); use moreau-jean";
  if (!world.constraints.empty() && parameters.linear_solver == "klu")
    return name + " eliminates linear constraints with a dense null-space basis: linear_solver klu is not "
                  "available with them; use linear_solver dense or auto";
  if (!world.constraints.empty() && world.velocity_size > kDenseLimit)
    return name + " eliminates linear constraints with a dense null-space basis, only for up to " +
           std::to_string(kDenseLimit) + " unknowns (this World has " + std::to_string(world.velocity_size) +
           "); use moreau-jean";
  if (parameters.events) {
    for (const BodyInstance& b : world.bodies)
      if (b.body->elastic())
        return "ida-events does not take elastic bodies (body '" + b.name +
               "'): its exact Coulomb mode holds a rigid interface; use ida (regularized contact) or moreau-jean";
    if (world.contact_laws.size() != 1)
      return "ida-events takes exactly one frictional interface (the scene has " +
             std::to_string(world.contact_laws.size()) + " contact laws); use ida or moreau-jean";
    const ContactLaw& law = world.contact_laws[0];
    if (world.bodies[law.body_a].body->fixed() == world.bodies[law.body_b].body->fixed())
      return "ida-events takes a contact between one moving and one fixed body (law '" + law.name +
             "'); use ida or moreau-jean";
  }
  return "";
}

IdaIntegrator::IdaIntegrator(const World& world, const IdaParameters& parameters)
    : world_(world), parameters_(parameters), dynamics_(world) {
  if (const std::string refusal = unsupported(world, parameters); !refusal.empty()) throw RunError(0.0, refusal);
  nq_ = world.position_size;
  nv_ = world.velocity_size;
  // Linear constraints are eliminated: v = N w with N an orthonormal basis of ker C (small Worlds).
  constrained_ = !world.constraints.empty();
  if (constrained_) {
    Matrix C = Matrix::Zero(world.constraints.size(), nv_);
    for (std::size_t e = 0; e < world.constraints.size(); ++e)
      for (const auto& [index, coefficient] : world.constraints[e].terms) C(e, index) += coefficient;
    Eigen::JacobiSVD<Matrix> svd(C, Eigen::ComputeFullV);
    const int rank = static_cast<int>((svd.singularValues().array() > 1e-12 * svd.singularValues().maxCoeff()).count());
    null_basis_ = svd.matrixV().rightCols(nv_ - rank);
    reduced_mass_ = null_basis_.transpose() * Matrix(dynamics_.mass()) * null_basis_;
    reduced_mass_factor_.compute(reduced_mass_);
    nr_ = static_cast<int>(null_basis_.cols());
  } else {
    mass_factor_.compute(dynamics_.mass());
    if (mass_factor_.info() != Eigen::Success || !(mass_factor_.vectorD().array() > 0.0).all())
      throw RunError(0.0, integrator_name(parameters.events ? Integrator::ida_events : Integrator::ida) +
                              ": the mass matrix is not positive definite (a body without mass?); use quasi-static");
    nr_ = nv_;
  }
  // The damping's energy row only when there is damping: a row that stays zero would dilute IDA's
  // error norm (a root mean square over the unknowns) and so loosen its tolerance.
  damped_ = dynamics_.has_damping();
  size_ = nq_ + nr_ + 2 + (damped_ ? 1 : 0);

  if (parameters.events) {
    Vector q0(nq_);
    for (const BodyInstance& b : world.bodies)
      q0.segment(b.position_offset, b.body->position_size()) = b.initial_position;
    Matrix projected_inverse_mass;
    if (constrained_) {
      projected_inverse_mass = null_basis_ * reduced_mass_factor_.solve(null_basis_.transpose());
    } else {
      const Matrix identity = Matrix::Identity(nv_, nv_);
      projected_inverse_mass = mass_factor_.solve(identity);
    }
    contact_model_ = std::make_unique<EventContactModel>(world, q0, projected_inverse_mass, parameters.sample_step);
  } else {
    auto regularized = std::make_unique<RegularizedContactModel>(dynamics_, parameters.penalty_stiffness,
                                                                 parameters.penalty_damping, parameters.epsilon,
                                                                 parameters.sample_step);
    regularized_ = regularized.get();
    contact_model_ = std::move(regularized);
  }
  q_.setZero(nq_);
  v_.setZero(nv_);
}

IdaIntegrator::~IdaIntegrator() = default;

void IdaIntegrator::summarize_statistics(const State& state, SummaryEntries& out) const {
  const IdaStatistics& ida = state.ida;
  out.begin_group("ida")
      .add("rtol", parameters_.rtol).add("atol", parameters_.atol)
      .add("linear_solver", ida.linear_solver)
      .add("jacobian", ida.linear_solver == "klu" ? "assembled from the tangents (ours, sparse)"
                                                  : "IDA difference quotients (dense)")
      .add("symbolic_analyses", ida.symbolic_analyses)
      .add("steps", ida.steps).add("residual_evaluations", ida.residual_evaluations)
      .add("jacobian_evaluations", ida.jacobian_evaluations)
      .add("error_test_failures", ida.error_test_failures)
      .add("nonlinear_convergence_failures", ida.nonlinear_convergence_failures)
      .add("last_step", ida.last_step)
      .add("epsilon", parameters_.epsilon);
  out.begin_group("penalty_stiffness");  // N/m, per contact law (the defaults resolved)
  for (std::size_t l = 0; l < ida.penalty_stiffness.size(); ++l)
    out.add(world_.contact_laws[l].name, ida.penalty_stiffness[l]);
  out.end_group();
  out.begin_group("penalty_damping");  // N·s/m, per contact law
  for (std::size_t l = 0; l < ida.penalty_damping.size(); ++l)
    out.add(world_.contact_laws[l].name, ida.penalty_damping[l]);
  out.end_group().end_group();
}

void IdaIntegrator::unpack(const double* y) {
  const Eigen::Map<const Vector> y_vector(y, size_);
  q_ = y_vector.head(nq_);
  if (constrained_) v_.noalias() = null_basis_ * y_vector.segment(nq_, nr_);
  else v_ = y_vector.segment(nq_, nr_);
}

void IdaIntegrator::smooth_forces(double t, const Vector& q, const Vector& v) {
  dynamics_.force(t, q, v, f_total_, &f_loads_, &f_damping_);
}

void IdaIntegrator::apply_reduced_mass(const Eigen::Ref<const Vector>& w_rate, Eigen::Ref<Vector> out) const {
  if (constrained_) out.noalias() = reduced_mass_ * w_rate;
  else out.noalias() = dynamics_.mass() * w_rate;
}

Vector IdaIntegrator::solve_reduced_mass(const Vector& b) const {
  return constrained_ ? Vector(reduced_mass_factor_.solve(b)) : Vector(mass_factor_.solve(b));
}

int IdaIntegrator::event_functions(double t, const double* y, const double*, double* g) {
  unpack(y);
  smooth_forces(t, q_, v_);
  contact_model_->events(t, q_, v_, f_total_, g);
  return 0;
}

int IdaIntegrator::residual(double t, const double* y, const double* y_rate, double* r) {
  const Eigen::Map<const Vector> rate(y_rate, size_);
  Eigen::Map<Vector> out(r, size_);
  unpack(y);

  q_rate_.resize(nq_);
  for (const BodyInstance& b : world_.bodies) {
    if (b.body->fixed()) continue;
    b.body->position_rate(b.positions(q_), v_.segment(b.velocity_offset, b.body->velocity_size()),
                          q_rate_.segment(b.position_offset, b.body->position_size()));
  }
  out.head(nq_) = rate.head(nq_) - q_rate_;

  smooth_forces(t, q_, v_);
  contact_model_->force(t, q_, v_, f_total_, f_contact_, nullptr);
  f_total_ += f_contact_;
  apply_reduced_mass(rate.segment(nq_, nr_), out.segment(nq_, nr_));
  if (constrained_) out.segment(nq_, nr_) -= null_basis_.transpose() * f_total_;
  else out.segment(nq_, nr_) -= f_total_;
  out(nq_ + nr_) = rate(nq_ + nr_) - f_loads_.dot(v_);
  out(nq_ + nr_ + 1) = rate(nq_ + nr_ + 1) + f_contact_.dot(v_);
  if (damped_) out(nq_ + nr_ + 2) = rate(nq_ + nr_ + 2) + f_damping_.dot(v_);
  return out.allFinite() ? 0 : 1;  // a recoverable error: IDA retries with a smaller step
}

// The assembled Jacobian of the header, J = ∂F/∂y + cj ∂F/∂y', on the union of the patterns seen so far.
int IdaIntegrator::sparse_jacobian(double t, double cj, const double* y, const double* y_rate, void* sparse_matrix) {
  SUNMatrix J = static_cast<SUNMatrix>(sparse_matrix);
  unpack(y);
  Triplets& entries = jacobian_triplets_;
  entries.clear();
  // Positions: cj I − ∂(Q(q) v)/∂q on q, −Q(q) on v (identity but for quaternions: differences per body).
  for (int i = 0; i < nq_; ++i) entries.emplace_back(i, i, cj);
  for (const BodyInstance& b : world_.bodies) {
    if (b.body->fixed()) continue;
    const int np = b.body->position_size(), m = b.body->velocity_size();
    if (b.body->position_rate_is_velocity()) {
      for (int c = 0; c < m; ++c) entries.emplace_back(b.position_offset + c, nq_ + b.velocity_offset + c, -1.0);
      continue;
    }
    Vector q_body = q_.segment(b.position_offset, np), v_body = v_.segment(b.velocity_offset, m);
    Vector plus(np), minus(np);
    for (int j = 0; j < np + m; ++j) {
      double& x = j < np ? q_body(j) : v_body(j - np);
      const double kept = x, delta = 1e-7 * std::max(1.0, std::abs(kept));
      x = kept + delta;
      b.body->position_rate(q_body, v_body, plus);
      x = kept - delta;
      b.body->position_rate(q_body, v_body, minus);
      x = kept;
      const int column = j < np ? b.position_offset + j : nq_ + b.velocity_offset + (j - np);
      for (int i = 0; i < np; ++i)
        if (const double value = -(plus(i) - minus(i)) / (2.0 * delta); value != 0.0)
          entries.emplace_back(b.position_offset + i, column, value);
    }
  }
  // Momentum: cj M + C + K(q) and the contact law's tangents (constrained Worlds are dense and small:
  // they take the internal difference quotients, see initialize).
  const int row0 = nq_, v0 = nq_;
  for (int k = 0; k < dynamics_.mass().outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(dynamics_.mass(), k); it; ++it)
      entries.emplace_back(row0 + it.row(), v0 + it.col(), cj * it.value());
  for (int k = 0; k < dynamics_.damping().outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(dynamics_.damping(), k); it; ++it)
      entries.emplace_back(row0 + it.row(), v0 + it.col(), it.value());
  Triplets stiffness, damping;
  dynamics_.add_stiffness(q_, stiffness);
  dynamics_.add_inertial_tangent(v_, damping);
  contact_model_->add_tangent(q_, v_, stiffness, damping);
  for (const auto& e : damping) entries.emplace_back(row0 + e.row(), v0 + e.col(), e.value());
  for (const auto& e : stiffness)
    if (const int column = dynamics_.position_of_velocity(e.col()); column >= 0) entries.emplace_back(row0 + e.row(), column, e.value());
  // Energy rows: their diagonal.
  for (int i = nq_ + nr_; i < size_; ++i) entries.emplace_back(i, i, cj);
  // The union with the patterns before, as explicit zeros.
  const bool first = jacobian_pattern_.size() == 0;
  for (int k = 0; k < jacobian_pattern_.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(jacobian_pattern_, k); it; ++it) entries.emplace_back(it.row(), it.col(), 0.0);
  SparseMatrix jacobian(size_, size_);
  jacobian.setFromTriplets(entries.begin(), entries.end());
  jacobian.makeCompressed();
  if (!Eigen::Map<const Vector>(jacobian.valuePtr(), jacobian.nonZeros()).allFinite()) return 1;  // recoverable: IDA retries with a smaller step
  const sunindextype nnz = jacobian.nonZeros();
  if (first || nnz != jacobian_pattern_.nonZeros()) {
    if (nnz > SM_NNZ_S(J) && SUNSparseMatrix_Reallocate(J, nnz) != 0) return -1;
    if (!first && SUNLinSol_KLUReInit(sundials_->solver, J, nnz, SUNKLU_REINIT_PARTIAL) != SUNLS_SUCCESS) return -1;
    jacobian_pattern_ = jacobian;
    ++symbolic_analyses_;
  }
  std::copy(jacobian.outerIndexPtr(), jacobian.outerIndexPtr() + size_ + 1, SM_INDEXPTRS_S(J));
  std::copy(jacobian.innerIndexPtr(), jacobian.innerIndexPtr() + nnz, SM_INDEXVALS_S(J));
  std::copy(jacobian.valuePtr(), jacobian.valuePtr() + nnz, SM_DATA_S(J));
  return 0;
}

// y' from the equations at the current y: q' = Q N w, w' = M_r⁻¹ Nᵀ f, and the energy rates; the
// residual at y' = 0 gives each of them up to the mass matrix.
void IdaIntegrator::consistent_rates(double t) {
  Sundials& s = *sundials_;
  Eigen::Map<Vector> y(N_VGetArrayPointer(s.y), size_), rate(N_VGetArrayPointer(s.y_rate), size_);
  rate.setZero();
  Vector at_zero_rate(size_);
  residual(t, y.data(), rate.data(), at_zero_rate.data());
  rate.head(nq_) = -at_zero_rate.head(nq_);
  rate.segment(nq_, nr_) = solve_reduced_mass(-at_zero_rate.segment(nq_, nr_));
  rate.tail(size_ - nq_ - nr_) = -at_zero_rate.tail(size_ - nq_ - nr_);
}

void IdaIntegrator::initialize(State& state) {
  sundials_ = std::make_unique<Sundials>();
  Sundials& s = *sundials_;
  if (SUNContext_Create(nullptr, &s.context) != 0) throw RunError(0.0, "SUNDIALS: cannot create a context");
  s.y = N_VNew_Serial(size_, s.context);
  s.y_rate = N_VNew_Serial(size_, s.context);
  Eigen::Map<Vector> y(N_VGetArrayPointer(s.y), size_);

  // Consistent initial values: w = Nᵀ v (v must satisfy the constraints), and y' from the equations.
  const Vector w0 = constrained_ ? Vector(null_basis_.transpose() * state.v) : state.v;
  if (constrained_ && (null_basis_ * w0 - state.v).norm() > 1e-12 * std::max(1.0, state.v.norm()))
    throw RunError(0.0, "the initial velocities violate the linear constraints");
  y.setZero();
  y.head(nq_) = state.q;
  y.segment(nq_, nr_) = w0;
  // The mode is chosen with the loads just after the start, so that a load ramped from zero at t = 0
  // is seen (it decides between stick and slip).
  smooth_forces(state.t + 1e-9 * parameters_.sample_step, state.q, state.v);
  contact_model_->choose_mode(state.t, state.q, state.v, f_total_);
  consistent_rates(state.t);

  s.memory = IDACreate(s.context);
  if (!s.memory) throw RunError(0.0, "SUNDIALS: IDACreate failed");
  IDASetErrHandlerFn(s.memory, error_callback, this);
  if (IDAInit(s.memory, residual_callback, state.t, s.y, s.y_rate) != IDA_SUCCESS)
    throw RunError(0.0, "IDAInit failed: " + last_error_);
  // Absolute tolerances per unknown: velocities no looser than ε/10, so that the error control
  // resolves the steep part of the regularized friction law (|u_t| ≲ ε); a looser velocity tolerance
  // lets the iterates wander across it and IDA crawls in stick phases at tiny steps.
  N_Vector absolute = N_VNew_Serial(size_, s.context);
  Eigen::Map<Vector> atol(N_VGetArrayPointer(absolute), size_);
  atol.setConstant(parameters_.atol);
  if (!parameters_.events && !world_.contact_laws.empty())
    atol.segment(nq_, nr_).setConstant(std::min(parameters_.atol, 0.1 * parameters_.epsilon));
  IDASVtolerances(s.memory, parameters_.rtol, absolute);
  N_VDestroy(absolute);
  IDASetUserData(s.memory, this);
  IDASetMaxNumSteps(s.memory, parameters_.max_steps);  // per sample; the run's total is checked in step()
  // BDF's local error test is no guarantee of global accuracy on an oscillator taken in a few long
  // steps: at rtol = 1e-10 and unbounded steps the SDNV104 extrema came out 1.6e-8 off, at steps no
  // longer than the 1e-3 s sample interval 4e-11. The reference mode therefore bounds its steps.
  const double max_step = parameters_.max_step > 0.0 ? parameters_.max_step
                                                     : (parameters_.events ? parameters_.sample_step : 0.0);
  if (max_step > 0.0) IDASetMaxStep(s.memory, max_step);

  // Constrained Worlds are small (unsupported) and dense: their Jacobian is left to IDA's quotients.
  const bool sparse = !constrained_ && (parameters_.linear_solver == "klu" ||
                                        (parameters_.linear_solver == "auto" && size_ > kDenseLimit));
  s.sparse = sparse;
  if (sparse) {
    s.matrix = SUNSparseMatrix(size_, size_, std::max(size_, 8 * size_), CSC_MAT, s.context);
    s.solver = SUNLinSol_KLU(s.y, s.matrix, s.context);
    // AMD on A + Aᵀ (0), not SUNDIALS' default COLAMD: the Jacobian's pattern is structurally symmetric
    // (that of M, K and C, in each block), and COLAMD's ordering fills it more (bench/ida_fe.md).
    if (s.solver) SUNLinSol_KLUSetOrdering(s.solver, 0);
  } else {
    s.matrix = SUNDenseMatrix(size_, size_, s.context);
    s.solver = SUNLinSol_Dense(s.y, s.matrix, s.context);
  }
  if (!s.matrix || !s.solver || IDASetLinearSolver(s.memory, s.solver, s.matrix) != IDALS_SUCCESS)
    throw RunError(0.0, "SUNDIALS: cannot set up the linear solver: " + last_error_);
  if (sparse) IDASetJacFn(s.memory, jacobian_callback);
  if (contact_model_->event_count() > 0) {
    IDARootInit(s.memory, contact_model_->event_count(), event_callback);
    std::vector<int> decreasing(contact_model_->event_count(), -1);
    IDASetRootDirection(s.memory, decreasing.data());
  }
  state.ida.linear_solver = sparse ? "klu" : "dense";
  if (regularized_)
    for (std::size_t l = 0; l < world_.contact_laws.size(); ++l) {
      state.ida.penalty_stiffness.push_back(regularized_->law(static_cast<int>(l)).stiffness);
      state.ida.penalty_damping.push_back(regularized_->law(static_cast<int>(l)).damping);
    }

  state.energy.kinetic = state.energy.initial_kinetic = dynamics_.kinetic_energy(state.v);
  contact_model_->force(state.t, state.q, state.v, f_total_, f_contact_, nullptr);
  state.energy.elastic = state.energy.initial_elastic =
      dynamics_.elastic_energy(state.q) + contact_model_->stored_energy();
  initial_stored_energy_ = contact_model_->stored_energy();
}

IdaStatistics IdaIntegrator::counters_since_restart() const {
  void* memory = sundials_->memory;
  IdaStatistics counters;
  long value = 0;
  IDAGetNumSteps(memory, &value);
  counters.steps = value;
  IDAGetNumResEvals(memory, &value);
  counters.residual_evaluations = value;
  IDAGetNumJacEvals(memory, &value);
  counters.jacobian_evaluations = value;
  IDAGetNumErrTestFails(memory, &value);
  counters.error_test_failures = value;
  IDAGetNumNonlinSolvConvFails(memory, &value);
  counters.nonlinear_convergence_failures = value;
  return counters;
}

void IdaIntegrator::fill_state(State& state) {
  Sundials& s = *sundials_;
  const Eigen::Map<const Vector> y(N_VGetArrayPointer(s.y), size_);
  state.q = y.head(nq_);
  if (constrained_) state.v = null_basis_ * y.segment(nq_, nr_);
  else state.v = y.segment(nq_, nr_);
  smooth_forces(state.t, state.q, state.v);
  contact_model_->force(state.t, state.q, state.v, f_total_, f_contact_, &state.contacts);
  // The penalty springs' energy is elastic energy, not dissipation (see the header).
  const double stored = contact_model_->stored_energy();
  EnergyBalance& e = state.energy;
  e.kinetic = dynamics_.kinetic_energy(state.v);
  e.elastic = dynamics_.elastic_energy(state.q) + stored;
  e.work_of_loads = y(nq_ + nr_);
  e.contact_dissipation = y(nq_ + nr_ + 1) - (stored - initial_stored_energy_);
  e.damping_dissipation = damped_ ? y(nq_ + nr_ + 2) : 0.0;
  e.max_abs_residual = std::max(e.max_abs_residual, std::abs(e.residual()));
  // IDA's counters, those before the last event's restart added (the solver's name and the penalties
  // were set by initialize).
  const IdaStatistics counters = counters_since_restart();
  IdaStatistics& stats = state.ida;
  stats.steps = counters.steps + before_restart_.steps;
  stats.residual_evaluations = counters.residual_evaluations + before_restart_.residual_evaluations;
  stats.jacobian_evaluations = counters.jacobian_evaluations + before_restart_.jacobian_evaluations;
  stats.error_test_failures = counters.error_test_failures + before_restart_.error_test_failures;
  stats.nonlinear_convergence_failures =
      counters.nonlinear_convergence_failures + before_restart_.nonlinear_convergence_failures;
  stats.symbolic_analyses = symbolic_analyses_;
  IDAGetLastStep(s.memory, &stats.last_step);
}

void IdaIntegrator::step(State& state) {
  Sundials& s = *sundials_;
  const double target = static_cast<double>(++sample_) * parameters_.sample_step;
  state.events.clear();
  double reached = state.t;
  int flag = IDA_SUCCESS;
  while (true) {
    flag = IDASolve(s.memory, target, &reached, s.y, s.y_rate, IDA_NORMAL);
    if (flag != IDA_ROOT_RETURN) break;
    // An event: record the exact state there, choose the new mode, restart IDA from it.
    unpack(N_VGetArrayPointer(s.y));
    state.events.push_back(EventSample{reached, q_, v_});
    smooth_forces(reached, q_, v_);
    contact_model_->choose_mode(reached, q_, v_, f_total_);
    consistent_rates(reached);
    const IdaStatistics counters = counters_since_restart();  // IDAReInit zeroes IDA's own counters
    before_restart_.steps += counters.steps;
    before_restart_.residual_evaluations += counters.residual_evaluations;
    before_restart_.jacobian_evaluations += counters.jacobian_evaluations;
    before_restart_.error_test_failures += counters.error_test_failures;
    before_restart_.nonlinear_convergence_failures += counters.nonlinear_convergence_failures;
    if (IDAReInit(s.memory, reached, s.y, s.y_rate) != IDA_SUCCESS)
      throw RunError(reached, "IDAReInit failed after an event: " + last_error_);
    if (reached >= target) break;
  }
  if (flag < 0 && flag != IDA_TOO_MUCH_WORK) {
    std::ostringstream message;
    message << "IDA failed at t = " << reached << " s (" << IDAGetReturnFlagName(flag) << ")";
    if (!last_error_.empty()) message << ": " << last_error_;
    throw RunError(reached, message.str());
  }
  state.t = flag == IDA_TOO_MUCH_WORK ? reached : target;
  fill_state(state);
  if (flag == IDA_TOO_MUCH_WORK || state.ida.steps > parameters_.max_steps) {
    std::ostringstream message;
    message << "IDA needed more than integrator.max_steps = " << parameters_.max_steps
            << " internal steps by t = " << state.t << " s (last step " << state.ida.last_step
            << " s): raise integrator.max_steps, or loosen the tolerances or the contact stiffness if the "
               "problem is too stiff for them";
    throw RunError(state.t, message.str());
  }
  if (!state.q.allFinite() || !state.v.allFinite()) throw RunError(target, "non-finite state from IDA");
  ++state.counters.steps;
}

}  // namespace csim
