// A sparse Delassus operator from scattered entries, its pattern completed to whole blocks: every
// dimension × dimension block between two contacts that holds an entry is stored in full (explicit zeros
// where the entries leave gaps), the layout friction_contact_problem.h promises for W_sparse. Used by the
// readers of problems from elsewhere, whose sparse formats store entries one by one.
#pragma once

#include "contact/friction_contact_problem.h"

#include <Eigen/SparseCore>
#include <vector>

namespace csim {

// size: rows (and columns) of W, a multiple of dimension; entries repeated add up (as in CSparse's and
// Eigen's triplet compression). Every entry must lie inside size × size.
SparseDelassus whole_blocks(int size, int dimension, const std::vector<Eigen::Triplet<double>>& entries);

}  // namespace csim
