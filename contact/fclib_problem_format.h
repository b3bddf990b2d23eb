// Reading a frictional contact problem from FCLib's HDF5 files (the Frictional Contact Library,
// FrictionalContactLibrary/fclib, src/fclib.h: fclib_write_local / fclib_read_local), the format in which
// this field exchanges problems. A local problem u = W r + q sits in the group /fclib_local:
//   spacedim          2 or 3 (the contact dimension d)
//   W/                a CSparse matrix: m, n, nzmax, nz and the arrays p, i, x, with
//                       nz ≥ 0: nz triplets (row i[k], column p[k], value x[k]);
//                       nz = −1: compressed columns (p: n + 1 column starts, i: row indices);
//                       nz = −2: compressed rows (p: m + 1 row starts, i: column indices);
//   vectors/q         m numbers
//   vectors/mu        m / d friction coefficients (an isotropic cone per contact)
// It becomes csim's FrictionContactProblem as a Siconos file does (siconos_problem_format.h): W_sparse
// (storage sparse, whole d × d blocks), b = q, mu[c] = (mu_c, mu_c), no equality rows. A problem with the
// optional V, R and s (bilateral constraints) or a global problem (/fclib_global) is refused by name.
//
// Errors throw std::runtime_error naming the dataset: a missing one, a size that does not fit, an index
// out of range, a non-finite value, a negative mu.
#pragma once

#include "contact/friction_contact_problem.h"

#include <string>

namespace csim {

// Whether the file starts with HDF5's signature (\x89HDF\r\n\x1a\n).
bool is_hdf5_file(const std::string& path);

FrictionContactProblem read_fclib_problem(const std::string& path);

}  // namespace csim
