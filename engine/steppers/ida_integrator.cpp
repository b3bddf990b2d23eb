#include "engine/steppers/ida_integrator.h"

#include "engine/steppers/event_contact_model.h"
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

int jacobian_callback(realtype t, realtype cj, N_Vector y, N_Vector yp, N_Vector r, SUNMatrix J, void* user,
                      N_Vector, N_Vector, N_Vector) {
  return static_cast<IdaIntegrator*>(user)->finite_difference_jacobian(
      t, cj, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), N_VGetArrayPointer(r), J);
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

IdaIntegrator::IdaIntegrator(const World& world, const IdaParameters& parameters)
    : world_(world), parameters_(parameters), forces_(world) {
  for (const BodyInstance& b : world.bodies)
    if (b.body->nonlinear()) throw RunError(0.0, "ida: body '" + b.name + "' is hyperelastic (not taken by ida yet)");
  if (!world.prescribed.empty() || !world.ties.empty())
    throw RunError(0.0, "ida: prescribed components and ties are taken by the quasi-static and Moreau-Jean steppers, not yet by IDA");
  for (const ContactLaw& law : world.contact_laws)
    if (law.mu_ramp_end > law.mu_ramp_start)
      throw RunError(0.0, "ida: contact law '" + law.name + "' has a mu_ramp (not taken by ida)");
  nq_ = world.position_size;
  nv_ = world.velocity_size;
  M_.setZero(nv_, nv_);
  Triplets mass;
  for (const BodyInstance& b : world.bodies) b.body->add_mass(b.velocity_offset, mass);
  for (const auto& entry : mass) M_(entry.row(), entry.col()) += entry.value();
  // Linear constraints are eliminated: v = N w with N an orthonormal basis of ker C.
  constrained_ = !world.constraints.empty();
  if (constrained_) {
    Matrix C = Matrix::Zero(world.constraints.size(), nv_);
    for (std::size_t e = 0; e < world.constraints.size(); ++e)
      for (const auto& [index, coefficient] : world.constraints[e].terms) C(e, index) += coefficient;
    Eigen::JacobiSVD<Matrix> svd(C, Eigen::ComputeFullV);
    const int rank = static_cast<int>((svd.singularValues().array() > 1e-12 * svd.singularValues().maxCoeff()).count());
    null_basis_ = svd.matrixV().rightCols(nv_ - rank);
  } else {
    null_basis_ = Matrix::Identity(nv_, nv_);
  }
  nr_ = static_cast<int>(null_basis_.cols());
  reduced_mass_ = null_basis_.transpose() * M_ * null_basis_;
  reduced_mass_factor_.compute(reduced_mass_);
  size_ = nq_ + nr_ + 2;

  if (parameters.events) {
    Vector q0(nq_);
    for (const BodyInstance& b : world.bodies)
      q0.segment(b.position_offset, b.body->position_size()) = b.initial_position;
    const Matrix projected_inverse_mass = null_basis_ * reduced_mass_factor_.solve(null_basis_.transpose());
    contact_model_ = std::make_unique<EventContactModel>(world, q0, projected_inverse_mass, parameters.sample_step);
  } else {
    contact_model_ = std::make_unique<RegularizedContactModel>(world, parameters.penalty_stiffness,
                                                               parameters.penalty_damping, parameters.epsilon,
                                                               parameters.sample_step);
  }
  q_.setZero(nq_);
  v_.setZero(nv_);
}

IdaIntegrator::~IdaIntegrator() = default;

void IdaIntegrator::unpack(const double* y) {
  const Eigen::Map<const Vector> y_vector(y, size_);
  q_ = y_vector.head(nq_);
  if (constrained_) v_.noalias() = null_basis_ * y_vector.segment(nq_, nr_);
  else v_ = y_vector.segment(nq_, nr_);
}

void IdaIntegrator::applied_forces(double t, const Vector& q, const Vector& v) {
  forces_.external(q, t, f_loads_);
  for (const BodyInstance& b : world_.bodies)
    b.body->add_inertial_force(v.segment(b.velocity_offset, b.body->velocity_size()),
                               f_loads_.segment(b.velocity_offset, b.body->velocity_size()));
  f_total_ = f_loads_;
  forces_.add_spring_forces(q, f_total_);
}

int IdaIntegrator::event_functions(double t, const double* y, const double*, double* g) {
  unpack(y);
  applied_forces(t, q_, v_);
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

  applied_forces(t, q_, v_);
  contact_model_->force(t, q_, v_, f_total_, f_contact_, nullptr);
  f_total_ += f_contact_;
  if (constrained_) out.segment(nq_, nr_) = reduced_mass_ * rate.segment(nq_, nr_) - null_basis_.transpose() * f_total_;
  else out.segment(nq_, nr_) = M_ * rate.segment(nq_, nr_) - f_total_;
  out(nq_ + nr_) = rate(nq_ + nr_) - f_loads_.dot(v_);
  out(nq_ + nr_ + 1) = rate(nq_ + nr_ + 1) + f_contact_.dot(v_);
  return out.allFinite() ? 0 : 1;  // a recoverable error: IDA retries with a smaller step
}

int IdaIntegrator::finite_difference_jacobian(double t, double cj, const double* y, const double* y_rate,
                                              const double* r, void* sparse_matrix) {
  SUNMatrix J = static_cast<SUNMatrix>(sparse_matrix);
  Vector y_shifted = Eigen::Map<const Vector>(y, size_), rate_shifted = Eigen::Map<const Vector>(y_rate, size_);
  const Eigen::Map<const Vector> r0(r, size_);
  Vector column(size_);
  std::vector<sunindextype> column_starts{0}, row_indices;
  std::vector<double> values;
  const double root_epsilon = std::sqrt(std::numeric_limits<double>::epsilon());
  for (int j = 0; j < size_; ++j) {
    const double delta = root_epsilon * std::max({std::abs(y[j]), std::abs(y_rate[j]) * parameters_.sample_step, 1e-8});
    y_shifted(j) += delta;
    rate_shifted(j) += cj * delta;
    if (residual(t, y_shifted.data(), rate_shifted.data(), column.data()) != 0) return 1;
    y_shifted(j) = y[j];
    rate_shifted(j) = y_rate[j];
    for (int i = 0; i < size_; ++i) {
      const double value = (column(i) - r0(i)) / delta;
      if (value != 0.0) {
        row_indices.push_back(i);
        values.push_back(value);
      }
    }
    column_starts.push_back(static_cast<sunindextype>(values.size()));
  }
  if (static_cast<sunindextype>(values.size()) > SM_NNZ_S(J))
    if (SUNSparseMatrix_Reallocate(J, static_cast<sunindextype>(values.size())) != 0) return -1;
  std::copy(column_starts.begin(), column_starts.end(), SM_INDEXPTRS_S(J));
  std::copy(row_indices.begin(), row_indices.end(), SM_INDEXVALS_S(J));
  std::copy(values.begin(), values.end(), SM_DATA_S(J));
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
  rate.segment(nq_, nr_) = reduced_mass_factor_.solve(-at_zero_rate.segment(nq_, nr_));
  rate.tail(2) = -at_zero_rate.tail(2);
}

void IdaIntegrator::initialize(State& state) {
  sundials_ = std::make_unique<Sundials>();
  Sundials& s = *sundials_;
  if (SUNContext_Create(nullptr, &s.context) != 0) throw RunError(0.0, "SUNDIALS: cannot create a context");
  s.y = N_VNew_Serial(size_, s.context);
  s.y_rate = N_VNew_Serial(size_, s.context);
  Eigen::Map<Vector> y(N_VGetArrayPointer(s.y), size_);

  // Consistent initial values: w = Nᵀ v (v must satisfy the constraints), and y' from the equations.
  const Vector w0 = null_basis_.transpose() * state.v;
  if ((null_basis_ * w0 - state.v).norm() > 1e-12 * std::max(1.0, state.v.norm()))
    throw RunError(0.0, "the initial velocities violate the linear constraints");
  y.setZero();
  y.head(nq_) = state.q;
  y.segment(nq_, nr_) = w0;
  // The mode is chosen with the loads just after the start, so that a load ramped from zero at t = 0
  // is seen (it decides between stick and slip).
  applied_forces(state.t + 1e-9 * parameters_.sample_step, state.q, state.v);
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

  const bool sparse = parameters_.linear_solver == "klu" ||
                      (parameters_.linear_solver == "auto" && size_ > kDenseLimit);
  s.sparse = sparse;
  if (sparse) {
    s.matrix = SUNSparseMatrix(size_, size_, std::max(size_, 8 * size_), CSC_MAT, s.context);
    s.solver = SUNLinSol_KLU(s.y, s.matrix, s.context);
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

  state.energy.kinetic = state.energy.initial_kinetic = 0.5 * state.v.dot(M_ * state.v);
  state.energy.elastic = state.energy.initial_elastic = forces_.elastic_energy(state.q);
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
  state.v = null_basis_ * y.segment(nq_, nr_);
  EnergyBalance& e = state.energy;
  e.kinetic = 0.5 * state.v.dot(M_ * state.v);
  e.elastic = forces_.elastic_energy(state.q);
  e.work_of_loads = y(nq_ + nr_);
  e.contact_dissipation = y(nq_ + nr_ + 1);
  e.max_abs_residual = std::max(e.max_abs_residual, std::abs(e.residual()));
  applied_forces(state.t, state.q, state.v);
  contact_model_->force(state.t, state.q, state.v, f_total_, f_contact_, &state.contacts);
  const std::string solver = state.ida.linear_solver;
  state.ida = counters_since_restart();
  state.ida.linear_solver = solver;
  IdaStatistics& stats = state.ida;
  stats.steps += before_restart_.steps;
  stats.residual_evaluations += before_restart_.residual_evaluations;
  stats.jacobian_evaluations += before_restart_.jacobian_evaluations;
  stats.error_test_failures += before_restart_.error_test_failures;
  stats.nonlinear_convergence_failures += before_restart_.nonlinear_convergence_failures;
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
    applied_forces(reached, q_, v_);
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
