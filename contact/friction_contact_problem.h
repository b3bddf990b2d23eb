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
#include <array>
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

// W by its factors, when the stepper's iteration matrix A is block diagonal by body (rigid bodies and
// point masses, nothing coupling two bodies): A_b = L_b L_bᵀ for each body b, and each contact c's rows on
// each of its (at most two) moving bodies scaled as K_cb = H_cb L_b⁻ᵀ (dimension × kBodySize, a body's
// velocity components padded with zeros to kBodySize), so that
//   W_cd = Σ_{b moved by both} K_cb K_dbᵀ,   (W r)_c = Σ_b K_cb w_b,   w_b = Σ_d K_dbᵀ r_d,
// w_b being L_bᵀ times the velocity change A_b⁻¹ H_bᵀ r of body b. Projected Gauss–Seidel on a sparse
// problem then applies W through w instead of reading W's block rows (sparse_pgs.h), as sequential-impulse
// solvers do: a contact's update reads and writes two bodies' w, whatever the number of its neighbours.
// Units: K in kg^(-1/2) (rows of H in m/s per body velocity, times L⁻ᵀ), w in kg^(1/2)·m/s.
struct BodyBlockDelassus {
  static constexpr int kBodySize = 6;
  int bodies = 0;                               // bodies are numbered [0, bodies)
  std::vector<std::array<int, 2>> body;         // each contact's two bodies, −1 for none (a fixed body)
  std::vector<double> scaled_rows;              // contact c, side s: K_cb at (2c + s) · dimension · kBodySize,
                                                // by rows (dimension rows of kBodySize)
  bool empty() const { return body.empty(); }
  void clear() {
    bodies = 0;
    body.clear();
    scaled_rows.clear();
  }
};

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
  // Optional, storage sparse without equality rows only: W's factors (above), one entry per contact, for
  // the solver to apply W through; W_sparse is then still the operator they form, for whatever reads it.
  BodyBlockDelassus body_blocks;

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
