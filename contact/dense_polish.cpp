// The polish of PgsSolver's dense path (pgs_solver.h, dense_pgs.h): the active-set iteration
// (active_set_polish.cpp), then Alart–Curnier Newton (alart_curnier.h), within a budget of flops.
#include "contact/alart_curnier.h"
#include "contact/dense_pgs.h"

namespace csim::dense_pgs {
namespace {

// Newton steps per polish; each costs a dense LU of the problem's size.
constexpr int kNewtonIterations = 30;

// Alart–Curnier Newton from `start` at each ρ scale in turn, until the residual reaches the tolerance;
// a result replaces r only if its full residual is smaller. True if r was replaced.
bool newton_polish(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, const Eigen::VectorXd& start,
                   Eigen::VectorXd& r, double& residual, double tolerance, PolishBudget& budget) {
  const double m = static_cast<double>(problem.size());
  bool improved = false;
  for (const double rho_scale : {1.0, 1e3}) {
    if (residual <= tolerance || budget.exhausted) break;
    Eigen::VectorXd candidate = start;
    NewtonStatistics newton;
    if (!alart_curnier_newton(problem, candidate, kNewtonIterations, 1e-3 * tolerance, &newton, rho_scale, &budget))
      break;
    if (newton.iterations == 0) continue;  // no step taken: the candidate is the start
    const double candidate_residual = relative_residual(problem, W_rows, candidate);
    budget.spent += 2.0 * m * m;
    if (candidate_residual < residual) {
      r = candidate;
      residual = candidate_residual;
      improved = true;
    }
  }
  return improved;
}

}  // namespace

// The polish: the active-set iteration from the iterate's statuses, then from "every closed contact in
// stick" (the usual state of a pressed interface, which a slowly converging iterate misclassifies at
// the cone's edge), then the semismooth Newton method (alart_curnier.h), which also finds slip
// directions in 3D. Each result is kept only if its full residual is smaller. All of it within `budget`:
// each factorization (the active set's, Newton's) is refused when the budget has no room for it.
//
// Newton starts from Gauss–Seidel's own iterate, not from an active-set result. A contact whose t2 row
// of W is zero (a node held across the ground's sliding direction: the plane-strain ring under a
// cornering ground, with a lateral slip of 1e-7 of the step's) can slip only along t2's fixed velocity;
// the active set may put it in stick with r_t2 = 0, a state whose residual looks smaller (the
// residual weighs r_t2 by W_cc, here zero) but from which Newton cannot move (its stick Jacobian row
// is zero) and the line search stops at once. From the Gauss–Seidel iterate, where the local solves
// have put that contact in slip, Newton converged in 2 to 10 steps on every such problem met
// (rolling-ring-3d on 34 × 5), where the former order left relative residuals of 3e-7 to 2e-6.
template <int D>
bool polish(const FrictionContactProblem& problem, const Eigen::MatrixXd& W_rows, Eigen::VectorXd& r, double& residual,
            double tolerance, PolishBudget& budget) {
  const Eigen::VectorXd iterate = r;
  bool moved_by_active_set = active_set_polish<D>(problem, W_rows, r, residual, false, budget);
  if (residual > tolerance && !budget.exhausted)
    moved_by_active_set = active_set_polish<D>(problem, W_rows, r, residual, true, budget) || moved_by_active_set;
  // Newton from the iterate, then from the active set's result if it differs (the former start, kept
  // second so that no problem the former order solved is lost).
  const Eigen::VectorXd active_set_result = r;
  bool improved = newton_polish(problem, W_rows, iterate, r, residual, tolerance, budget) || moved_by_active_set;
  if (moved_by_active_set)
    improved = newton_polish(problem, W_rows, active_set_result, r, residual, tolerance, budget) || improved;
  return improved;
}


template bool polish<2>(const FrictionContactProblem&, const Eigen::MatrixXd&, Eigen::VectorXd&, double&, double,
                        PolishBudget&);
template bool polish<3>(const FrictionContactProblem&, const Eigen::MatrixXd&, Eigen::VectorXd&, double&, double,
                        PolishBudget&);

}  // namespace csim::dense_pgs
