// The quasi-static stepper: incremental loading without inertia, with the same frictional contact
// solve as Moreau–Jean, on the stiffness instead of the iteration matrix.
//
// A load step from t_k to t_{k+1} (a pseudo-time: the loads' multipliers λ(t) give the loading path):
//   free solution   K u_free = f(t_{k+1})            (linear elastic bodies and springs: K constant,
//                                                     factored once; total, not incremental, form)
//   detect          contacts whose gap is ≤ integrator.contact_distance (the closure a load step may
//                   bring), at u_k, with their frames and rows H;
//   contact problem u = W r + q with W = H K⁻¹ Hᵀ, q = H (u_free − u_k) + (g_k on the normal rows):
//                   the normal "velocity" is the gap at the end of the step, g_k + H_n Δu, so that
//                   Signorini holds at the position level; the tangential one is the slip increment,
//                   and Coulomb's law acts on it (r: forces, N);
//   update          u_{k+1} = u_free + K⁻¹ Hᵀ r.
// Applied in sequence (normal load first, then tangential, SPEC.md §4.3), the increments follow the
// loading path that the friction law depends on. State velocities hold Δu / h, impulses r·h (so that
// contact-force probes read r). Every free body must be held by stiffness (K nonsingular).
#pragma once

#include "contact/pgs_solver.h"
#include "engine/contact_detector.h"
#include "engine/forces.h"
#include "engine/steppers/moreau_jean.h"
#include "engine/steppers/stepper.h"

#include <Eigen/SparseCholesky>

namespace csim {

struct QuasiStaticParameters {
  double step = 0.1;              // s of pseudo-time per load step
  double contact_distance = 0.0;  // m; 0 = 10 % of the largest body's bounding radius
  PgsParameters solver;
  double failure_residual = 1e-6;
};

class QuasiStatic final : public Stepper {
 public:
  QuasiStatic(const World& world, const QuasiStaticParameters& parameters);

  void initialize(State& state) override;
  void step(State& state) override;
  double time_step() const override { return parameters_.step; }

 private:
  const World& world_;
  QuasiStaticParameters parameters_;
  ForceModel forces_;
  ContactDetector detector_;
  PgsSolver pgs_;
  Eigen::SimplicialLDLT<SparseMatrix> stiffness_factor_;
  SparseMatrix stiffness_;
  double contact_distance_;
  int d_;

  Vector f_, u_free_, u_next_, r_;
  std::vector<ActiveContact> candidates_, active_;
  std::vector<SparseRow> rows_;
  Matrix H_, X_;
  FrictionContactProblem problem_;
};

}  // namespace csim
