// The one-step frictional contact problem of a nonsmooth time-stepper, as a plain value.
//
//   u = W r + b
//
// W is the Delassus operator H A⁻¹ Hᵀ (A: the stepper's iteration matrix, H: the contact rows) and b
// the local free term (H times the free solution, plus the stepper's terms on the normal rows). The
// units are the stepper's:
//   Moreau–Jean (velocity level): r impulses (N·s), u local relative velocities after the step (m/s),
//     b the local free velocity (m/s, with the Newton impact term e·u_n⁻ folded into its normal rows),
//     W (1/kg: m/s per N·s);
//   quasi-static (position level): r forces (N), u the gap and slip at the end of the step (m), b their
//     free value (m), W (m/N).
// (Rows of angular or constraint coordinates scale the same way with their own units.) The text format
// of write_problem keeps the keyword `q` for b, so that problems dumped earlier still load.
//
// Row layout: contacts first, `dimension` rows each, ordered [n, t1] (dimension 2) or [n, t1, t2]
// (dimension 3); then `equalities` bilateral rows (linear kinematic constraints, u = 0, r free).
//
// Per contact c, the Coulomb law with anisotropic (orthotropic) coefficients mu[c] = (μ1, μ2) along
// (t1, t2) (Signorini + Coulomb, De Saxcé & Feng 1998):
//   0 ≤ u_n ⊥ r_n ≥ 0
//   r_t ∈ D(r_n) = { r_t : (r_t1/μ1)² + (r_t2/μ2)² ≤ r_n² }   (a zero μ_i forces r_ti = 0)
//   r_t maximises dissipation:  -r_t·u_t = max over D(r_n)   (stick: u_t = 0; slip: r_t on ∂D)
// The sign convention is that of the contact frame: n points from body A to body B, u = v_B − v_A at
// the contact point, and a positive r_n pushes B away from A.
#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <iosfwd>
#include <string>
#include <vector>

namespace csim {

// W's storage. Dense: a few contacts, or a World whose contacts all couple (the nodes of one elastic
// body). Sparse: rows stored compressed (CSR), the nonzero pattern made of whole dimension × dimension
// blocks between two contacts that share a body (and whole rows and columns for the equalities), so that
// memory and a Gauss–Seidel sweep cost O(nonzero blocks): a pile's W has 0.3 % nonzero blocks.
enum class DelassusStorage { dense, sparse };
using SparseDelassus = Eigen::SparseMatrix<double, Eigen::RowMajor>;

struct FrictionContactProblem {
  int dimension = 3;        // 2 (plane problems) or 3
  int contacts = 0;         // number of contacts
  int equalities = 0;       // number of bilateral rows after the contact rows
  DelassusStorage storage = DelassusStorage::dense;  // which of W and W_sparse holds the Delassus operator
  Eigen::MatrixXd W;        // storage dense: Delassus, (dimension·contacts + equalities)²; the steppers' is symmetric
                            // positive semi-definite, a problem from elsewhere may be unsymmetric (pgs_solver.h reads rows)
  SparseDelassus W_sparse;  // storage sparse: the same operator, same size and row order; W is then empty
  Eigen::VectorXd b;        // free term: local free velocity (m/s) or free gap and slip (m), same size
  std::vector<Eigen::Vector2d> mu;  // per contact (μ1, μ2), dimensionless, ≥ 0; dimension 2 uses μ1 only

  int size() const { return dimension * contacts + equalities; }
};

// Why the sizes of a problem do not fit together, or "" when they do.
std::string inconsistency(const FrictionContactProblem& problem);

// Plain-text format (one keyword line, then numbers), so a problem met in a run can be dumped and
// replayed in a unit test. Throws std::runtime_error on malformed input (and write_problem on an
// inconsistent problem). Numbers round-trip bit for bit, nan/inf included; the layout is described in
// friction_contact_problem.cpp.
void write_problem(std::ostream& out, const FrictionContactProblem& problem);
FrictionContactProblem read_problem(std::istream& in);

}  // namespace csim
