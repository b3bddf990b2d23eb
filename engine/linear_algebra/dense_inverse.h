// The explicit inverse of a small symmetric positive definite matrix (the iteration matrix A of a
// lumped World, n ≤ StructuralOperators::kDenseLimit). A lumped step applies A⁻¹ a dozen times (the
// free velocity, one Delassus column per contact row): kept explicitly, each is a mat-vec, and a
// Delassus column A⁻¹ hᵀ is the combination of A⁻¹'s columns weighted by the row's few entries, where
// a factorization would cost a pair of triangular solves each. For these matrices (mass-dominated,
// well conditioned) the inverse is as accurate as the solves, to round-off.
#pragma once

#include "engine/bodies/body.h"

namespace csim {

// inverse ← A⁻¹ by Cholesky, A = L Lᵀ, A⁻¹ = L⁻ᵀ L⁻¹ (one triangle computed and mirrored: exactly
// symmetric). Returns false when a pivot is not positive (A is not positive definite); `inverse` is
// then unspecified. `factor` is scratch. No allocation once factor and inverse have A's size.
bool invert_positive_definite(const Matrix& A, Matrix& factor, Matrix& inverse);

}  // namespace csim
