// Reading a frictional contact problem in Siconos numerics' text format, the files written by
// `frictionContact_printInFile` (numerics/src/FrictionContact/FrictionContactProblem.c) and read by
// `frictionContact_newFromFile`: Siconos' own test problems (numerics/src/FrictionContact/test/data)
// and what a Siconos simulation dumps.
//
// Layout (whitespace between numbers is free, as for the fscanf that reads it):
//   d                       dimension, 2 or 3
//   nc                      number of contacts
//   M                       the matrix W, written by NM_write_in_file (NumericsMatrix.c):
//     storage size0 size1     storage 0 dense, 1 sparse-block (SBM), 2 sparse (CSparse)
//     dense:  size0 size1, then size0·size1 numbers in column-major order (entry (i, j) is the
//             number i + j·size0);
//     SBM (SparseBlockMatrix.c, SBM_write_in_file): nbblocks, blocknumber0, blocknumber1, the
//             cumulated row sizes of the block rows (blocknumber0 numbers), the same for the block
//             columns, filled1, filled2, index1_data (filled1 row pointers into the blocks), index2_data
//             (filled2 block-column indices), then each block in that order: its index, then its
//             rows·cols numbers in column-major order;
//     sparse (NumericsSparseMatrix.c, CSparseMatrix.c): an origin number, then CSparse's print of the
//             matrix: a version line, a line "[triplet: |csr: ]m-by-n, nzmax: … nnz: …", then per
//             column "col j : locations p to q" and its entries "i : value" (values printed with %g,
//             6 significant digits), per row "row i …" for csr, or "i j : value" triplets;
//   q                       size0 numbers
//   mu                      nc numbers, one friction coefficient per contact
// After mu, one token at most (several of Siconos' files end with a flag, 0 or 1), which is ignored as
// Siconos' reader ignores it. More is refused: a GlobalFrictionContactProblem file (GFC3D_*.dat) starts
// the same way, and reading its first part as this problem would solve another problem silently.
//
// The problem is Siconos' u = M r + q with r, u in [n, t1(, t2)] order per contact and an isotropic
// Coulomb cone of coefficient mu: csim's FrictionContactProblem (friction_contact_problem.h) with W = M,
// b = q, mu[c] = (mu_c, mu_c) and no equality rows; same units as the file (Siconos' are the stepper's,
// as csim's). A dense file gives storage dense (W); a sparse-block or sparse file gives storage sparse
// (W_sparse), its pattern completed to whole d × d blocks with explicit zeros, so that a 7002-contact
// problem loads in O(nonzero blocks) memory. A sparse file is read as its print says (a "col" list is
// compressed columns): Siconos 4.4 reads the granular-flow files the same way (origin 2 = NSM_CSC there).
//
// Errors throw ProblemFileError with the 1-based line of the offending token: a malformed or
// non-finite number, a size that does not fit the dimension and contact count, a negative mu, a block
// structure that does not cover whole contacts, input that ends early or goes on after mu.
#pragma once

#include "contact/friction_contact_problem.h"

#include <iosfwd>
#include <stdexcept>
#include <string>

namespace csim {

class ProblemFileError : public std::runtime_error {
 public:
  ProblemFileError(int line, const std::string& message)
      : std::runtime_error("line " + std::to_string(line) + ": " + message), line_(line), message_(message) {}
  int line() const { return line_; }                      // 1-based
  const std::string& message() const { return message_; }  // without the line
 private:
  int line_;
  std::string message_;
};

FrictionContactProblem read_siconos_problem(std::istream& in);

}  // namespace csim
