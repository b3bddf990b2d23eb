// Islands of a frictional contact problem: the connected components of W's block pattern. Two contacts
// are coupled when their block of W is nonzero, that is when they share a body that moves; contacts on
// bodies that touch nothing else in common form separate islands (a pile's columns, boxes apart on a
// floor: the fixed floor couples nothing; a problem with W's body-block factors, friction_contact_problem.h,
// is split by its contacts' bodies). W is block diagonal over the islands, so the problem splits
// into independent ones, each solved alone (Bullet's and MuJoCo's islands; Siconos' interaction graph).
//
// Why it pays: Gauss–Seidel's stopping test and the polish's factorizations then see one island at a
// time: an island that converges stops sweeping, and a stalled island is polished on its own rows (a
// dense LU of a few dozen rows instead of a sparse factorization of the whole set).
#pragma once

#include "contact/coulomb_local.h"
#include "contact/friction_contact_problem.h"

#include <Eigen/Dense>
#include <vector>

namespace csim {

// The contacts of each island, in increasing order, islands ordered by their first contact. A problem
// with equality rows is one island (a constraint may join anything); so is a problem without contacts.
std::vector<std::vector<int>> find_islands(const FrictionContactProblem& problem);

// The sub-problem of the given contacts (an island: no coupling to the others), W stored as `storage`.
FrictionContactProblem island_problem(const FrictionContactProblem& problem, const std::vector<int>& contacts,
                                      DelassusStorage storage);

// Copies the island's impulses (and statuses, when given) into the whole problem's.
void scatter_island(const std::vector<int>& contacts, int dimension, const Eigen::VectorXd& island_r,
                    const std::vector<ContactStatus>* island_status, Eigen::VectorXd& r,
                    std::vector<ContactStatus>* status);

// The island's part of the whole problem's r.
Eigen::VectorXd gather_island(const std::vector<int>& contacts, int dimension, const Eigen::VectorXd& r);

}  // namespace csim
