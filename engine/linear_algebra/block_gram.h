// The Delassus operator W = Yᵀ D⁻¹ Y of the forward columns y_a = L⁻¹ P h_aᵀ of a problem's rows
// (sparse_ldlt.h), stored sparse: W_ab = y_aᵀ D⁻¹ y_b is zero unless the two columns share a row of the
// factor, which for bodies that A does not couple (rigid bodies, points, separate elastic bodies) means
// unless the two rows move a common body. A pile of spheres has a few nonzero 3 × 3 blocks a row, where a
// dense W has m² entries: memory and the Gauss–Seidel sweep then cost O(nonzero blocks).
//
// Storage and cost: block_pattern.h, the indices a column reaches being its factor rows; then one sparse
// dot for each entry of the pattern's upper triangle.
#pragma once

#include "engine/linear_algebra/sparse_ldlt.h"

#include <Eigen/SparseCore>
#include <vector>

namespace csim {

// W (columns.size() square) from these forward columns of one factor's rows; dimension: 2 or 3;
// contacts: how many leading blocks of `dimension` columns are contacts. Returns false, W untouched,
// when some factor row is reached by more than max_density × (number of blocks) blocks: W would then
// be dense in at least that fraction of its block rows (the contacts of one elastic body), and the
// dense storage is faster (the test costs O(Σ |y_a|) at most, and stops at the first such row).
bool block_gram(const SparseLdlt& factor, const std::vector<const SparseLdlt::ForwardColumn*>& columns,
                int dimension, int contacts, Eigen::SparseMatrix<double, Eigen::RowMajor>& W,
                double max_density = 1.0);

}  // namespace csim
