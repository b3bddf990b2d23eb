// The rows H of one contact problem, in the problem's order: each active contact's `dimension` rows
// (normal, then tangents: contact i owns rows [d·i, d·(i+1))), then the equality rows (the World's linear
// constraints and the active prescriptions, dense), then the ties' rows (tie_rows.h). u = H v (m/s, rad/s
// on rotation components) is the velocity the problem's impulses r (N·s) act on; Hᵀ r is their
// generalized impulse. Rows are pointed at, not copied: they belong to the detection and the stepper.
#pragma once

#include "contact/contact_point.h"
#include "engine/linear_algebra/sparse_row.h"

#include <vector>

namespace csim {

struct ProblemRows {
  int dimension = 3;
  std::vector<const SparseRow*> contact;     // the active contacts' rows
  std::vector<int> contact_candidate;        // each active contact's index among the detection's candidates
  std::vector<ContactKey> contact_key;       // each active contact's key (its rows' identity)
  int candidates = 0;                        // how many candidates the detection gave
  const Matrix* equalities = nullptr;        // ne × n, or none
  const std::vector<SparseRow>* ties = nullptr;

  int contact_rows() const { return static_cast<int>(contact.size()); }
  int equality_rows() const { return equalities ? static_cast<int>(equalities->rows()) : 0; }
  int tie_rows() const { return ties ? static_cast<int>(ties->size()) : 0; }
  int size() const { return contact_rows() + equality_rows() + tie_rows(); }

  // Row a · v.
  double dot(int a, const Vector& v) const {
    const int nc = contact_rows(), ne = equality_rows();
    if (a < nc) return contact[a]->dot(v);
    if (a < nc + ne) return equalities->row(a - nc).dot(v);
    return (*ties)[a - nc - ne].dot(v);
  }
  // out += scale · (row a)ᵀ (out a Vector, or a column or row of a dense matrix).
  template <class Dense>
  void scatter(int a, double scale, Dense&& out) const {
    const int nc = contact_rows(), ne = equality_rows();
    if (a < nc) {
      contact[a]->scatter(scale, out);
    } else if (a < nc + ne) {
      for (int j = 0; j < equalities->cols(); ++j) out(j) += scale * (*equalities)(a - nc, j);
    } else {
      (*ties)[a - nc - ne].scatter(scale, out);
    }
  }
  // Row a's place among the rows of every candidate (d each, in the detection's order) followed by the
  // equalities' (no ties): the rows whose forward columns the two halves of Moreau–Jean keep.
  int candidate_row(int a) const {
    const int nc = contact_rows();
    return a < nc ? dimension * contact_candidate[a / dimension] + a % dimension : dimension * candidates + (a - nc);
  }
};

}  // namespace csim
