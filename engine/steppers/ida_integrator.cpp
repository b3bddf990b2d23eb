#include "engine/steppers/ida_integrator.h"

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

ConstVectorRef positions_of(const BodyInstance& b, const Vector& q) {
  return q.segment(b.position_offset, b.body->position_size());
}

int residual_callback(realtype t, N_Vector y, N_Vector yp, N_Vector r, void* user) {
  return static_cast<IdaIntegrator*>(user)->residual(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp),
                                                     N_VGetArrayPointer(r));
}

int jacobian_callback(realtype t, realtype cj, N_Vector y, N_Vector yp, N_Vector r, SUNMatrix J, void* user,
                      N_Vector, N_Vector, N_Vector) {
  return static_cast<IdaIntegrator*>(user)->finite_difference_jacobian(
      t, cj, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), N_VGetArrayPointer(r), J);
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
    : world_(world), parameters_(parameters), forces_(world), detector_(world) {
  nq_ = world.position_size;
  nv_ = world.velocity_size;
  M_.setZero(nv_, nv_);
  double heaviest = 0.0;
  for (const BodyInstance& b : world.bodies) {
    b.body->add_mass(M_.block(b.velocity_offset, b.velocity_offset, b.body->velocity_size(), b.body->velocity_size()));
    heaviest = std::max(heaviest, b.body->mass());
  }
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

  const double k = parameters.penalty_stiffness > 0.0 ? parameters.penalty_stiffness : 1e8 * heaviest;
  for (const ContactLaw& law : world.contact_laws) {
    RegularizedContactLaw regularized;
    regularized.stiffness = k;
    regularized.epsilon = parameters.epsilon;
    regularized.mu = law.mu;
    double inverse_mass = 0.0;
    for (int body : {law.body_a, law.body_b})
      if (!world.bodies[body].body->fixed()) inverse_mass += 1.0 / world.bodies[body].body->mass();
    const double effective_mass = inverse_mass > 0.0 ? 1.0 / inverse_mass : 0.0;
    regularized.damping = parameters.penalty_damping >= 0.0
                              ? parameters.penalty_damping
                              : 2.0 * damping_ratio_for_restitution(law.restitution) * std::sqrt(k * effective_mass);
    laws_.push_back(regularized);
  }
  q_.setZero(nq_);
  v_.setZero(nv_);
}

IdaIntegrator::~IdaIntegrator() = default;

void IdaIntegrator::contact_forces(const Vector& q, const Vector& v, Vector& f, std::vector<ActiveContact>* record) {
  f.setZero(nv_);
  if (detector_.empty()) return;
  detector_.detect(q, 0.0, contacts_, rows_);
  const int d = detector_.dimension();
  for (std::size_t i = 0; i < contacts_.size(); ++i) {
    ActiveContact& c = contacts_[i];
    const auto rows = rows_.middleRows(d * i, d);
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    u.head(d) = rows * v;
    const Eigen::Vector3d force = regularized_contact_force(laws_[c.law], c.point.gap, u, d);
    f.noalias() += rows.transpose() * force.head(d);
    c.impulse = force * parameters_.sample_step;  // probes read impulses over a sample interval
    c.status = force(0) == 0.0 ? ContactStatus::open : ContactStatus::slip;
  }
  if (record) *record = contacts_;
}

int IdaIntegrator::residual(double t, const double* y, const double* y_rate, double* r) {
  const Eigen::Map<const Vector> y_vector(y, size_), rate(y_rate, size_);
  Eigen::Map<Vector> out(r, size_);
  q_ = y_vector.head(nq_);
  if (constrained_) v_.noalias() = null_basis_ * y_vector.segment(nq_, nr_);
  else v_ = y_vector.segment(nq_, nr_);

  q_rate_.resize(nq_);
  for (const BodyInstance& b : world_.bodies) {
    if (b.body->fixed()) continue;
    b.body->position_rate(positions_of(b, q_), v_.segment(b.velocity_offset, b.body->velocity_size()),
                          q_rate_.segment(b.position_offset, b.body->position_size()));
  }
  out.head(nq_) = rate.head(nq_) - q_rate_;

  forces_.external(q_, t, f_loads_);
  for (const BodyInstance& b : world_.bodies)
    b.body->add_inertial_force(v_.segment(b.velocity_offset, b.body->velocity_size()),
                               f_loads_.segment(b.velocity_offset, b.body->velocity_size()));
  f_total_ = f_loads_;
  forces_.add_spring_forces(q_, f_total_);
  contact_forces(q_, v_, f_contact_, nullptr);
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

void IdaIntegrator::initialize(State& state) {
  sundials_ = std::make_unique<Sundials>();
  Sundials& s = *sundials_;
  if (SUNContext_Create(nullptr, &s.context) != 0) throw RunError(0.0, "SUNDIALS: cannot create a context");
  s.y = N_VNew_Serial(size_, s.context);
  s.y_rate = N_VNew_Serial(size_, s.context);
  Eigen::Map<Vector> y(N_VGetArrayPointer(s.y), size_), rate(N_VGetArrayPointer(s.y_rate), size_);

  // Consistent initial values: w = Nᵀ v (v must satisfy the constraints), and y' from the equations.
  const Vector w0 = null_basis_.transpose() * state.v;
  if ((null_basis_ * w0 - state.v).norm() > 1e-12 * std::max(1.0, state.v.norm()))
    throw RunError(0.0, "the initial velocities violate the linear constraints");
  y.setZero();
  y.head(nq_) = state.q;
  y.segment(nq_, nr_) = w0;
  rate.setZero();
  std::vector<double> r0(size_);
  residual(state.t, y.data(), rate.data(), r0.data());
  const Eigen::Map<const Vector> at_zero_rate(r0.data(), size_);
  rate.head(nq_) = -at_zero_rate.head(nq_);                                  // q' = Q N w
  rate.segment(nq_, nr_) = reduced_mass_factor_.solve(-at_zero_rate.segment(nq_, nr_));  // M_r w' = Nᵀ f
  rate.tail(2) = -at_zero_rate.tail(2);

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
  if (!world_.contact_laws.empty())
    atol.segment(nq_, nr_).setConstant(std::min(parameters_.atol, 0.1 * parameters_.epsilon));
  IDASVtolerances(s.memory, parameters_.rtol, absolute);
  N_VDestroy(absolute);
  IDASetUserData(s.memory, this);
  IDASetMaxNumSteps(s.memory, parameters_.max_steps);  // per sample; the run's total is checked in step()

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
  state.ida.linear_solver = sparse ? "klu" : "dense";

  state.energy.kinetic = state.energy.initial_kinetic = 0.5 * state.v.dot(M_ * state.v);
  state.energy.elastic = state.energy.initial_elastic = forces_.elastic_energy(state.q);
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
  contact_forces(state.q, state.v, f_contact_, &state.contacts);
  long value = 0;
  IdaStatistics& stats = state.ida;
  IDAGetNumSteps(s.memory, &value);
  stats.steps = value;
  IDAGetNumResEvals(s.memory, &value);
  stats.residual_evaluations = value;
  IDAGetNumJacEvals(s.memory, &value);
  stats.jacobian_evaluations = value;
  IDAGetNumErrTestFails(s.memory, &value);
  stats.error_test_failures = value;
  IDAGetNumNonlinSolvConvFails(s.memory, &value);
  stats.nonlinear_convergence_failures = value;
  IDAGetLastStep(s.memory, &stats.last_step);
}

void IdaIntegrator::step(State& state) {
  Sundials& s = *sundials_;
  const double target = static_cast<double>(++sample_) * parameters_.sample_step;
  double reached = state.t;
  const int flag = IDASolve(s.memory, target, &reached, s.y, s.y_rate, IDA_NORMAL);
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
            << " s): the regularized problem is too stiff for these tolerances";
    throw RunError(state.t, message.str());
  }
  if (!state.q.allFinite() || !state.v.allFinite())
    throw RunError(target, "non-finite state from IDA");
  ++state.counters.steps;
}

}  // namespace csim
