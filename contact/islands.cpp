#include "contact/islands.h"

#include <numeric>

namespace csim {

namespace {

// Union–find over contacts, by size, with path halving.
class DisjointSets {
 public:
  explicit DisjointSets(int n) : parent_(n), size_(n, 1) { std::iota(parent_.begin(), parent_.end(), 0); }
  int root(int i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  void join(int a, int b) {
    a = root(a);
    b = root(b);
    if (a == b) return;
    if (size_[a] < size_[b]) std::swap(a, b);
    parent_[b] = a;
    size_[a] += size_[b];
  }

 private:
  std::vector<int> parent_, size_;
};

}  // namespace

std::vector<std::vector<int>> find_islands(const FrictionContactProblem& problem) {
  const int n = problem.contacts, d = problem.dimension;
  std::vector<std::vector<int>> islands;
  if (n == 0) return islands;
  if (problem.equalities > 0) {
    islands.emplace_back(n);
    std::iota(islands[0].begin(), islands[0].end(), 0);
    return islands;
  }
  DisjointSets sets(n);
  if (const BodyBlockDelassus& blocks = problem.body_blocks; !blocks.empty()) {
    // W by its body-block factors: contacts that move a common body, read from the bodies (O(contacts)
    // where W's pattern is O(stored entries)); a block of W that cancels to zero between two contacts of
    // one body still joins them, as the definition above has it.
    std::vector<int> first_contact(static_cast<std::size_t>(blocks.bodies), -1);
    for (int c = 0; c < n; ++c)
      for (const int b : blocks.body[c]) {
        if (b < 0) continue;
        if (first_contact[b] < 0) first_contact[b] = c;
        else sets.join(first_contact[b], c);
      }
  } else if (problem.storage == DelassusStorage::sparse) {
    const SparseDelassus& W = problem.W_sparse;
    for (int row = 0; row < W.outerSize(); ++row)
      for (SparseDelassus::InnerIterator it(W, row); it; ++it)
        if (it.value() != 0.0) sets.join(row / d, static_cast<int>(it.col()) / d);
  } else {
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b)
        if (!problem.W.block(d * a, d * b, d, d).isZero(0.0) || !problem.W.block(d * b, d * a, d, d).isZero(0.0))
          sets.join(a, b);
  }
  std::vector<int> island_of_root(n, -1);
  for (int c = 0; c < n; ++c) {
    int& island = island_of_root[sets.root(c)];
    if (island < 0) {
      island = static_cast<int>(islands.size());
      islands.emplace_back();
    }
    islands[island].push_back(c);
  }
  return islands;
}

namespace {

// The island's share of W's body-block factors (friction_contact_problem.h), the bodies numbered as in
// the whole problem.
void island_body_blocks(const FrictionContactProblem& problem, const std::vector<int>& contacts,
                        FrictionContactProblem& island) {
  const BodyBlockDelassus& whole = problem.body_blocks;
  if (whole.empty()) return;
  BodyBlockDelassus& part = island.body_blocks;
  const std::size_t side = static_cast<std::size_t>(problem.dimension) * BodyBlockDelassus::kBodySize;
  part.bodies = whole.bodies;
  part.body.reserve(contacts.size());
  part.scaled_rows.reserve(2 * side * contacts.size());
  for (const int c : contacts) {
    part.body.push_back(whole.body[c]);
    part.scaled_rows.insert(part.scaled_rows.end(), whole.scaled_rows.begin() + 2 * side * c,
                            whole.scaled_rows.begin() + 2 * side * (c + 1));
  }
}

}  // namespace

FrictionContactProblem island_problem(const FrictionContactProblem& problem, const std::vector<int>& contacts,
                                      DelassusStorage storage) {
  const int d = problem.dimension, n = static_cast<int>(contacts.size());
  FrictionContactProblem island;
  island.dimension = d;
  island.contacts = n;
  island.storage = storage;
  island.b.resize(d * n);
  island.mu.resize(n);
  std::vector<int> local(problem.contacts, -1);
  for (int i = 0; i < n; ++i) {
    local[contacts[i]] = i;
    island.b.segment(d * i, d) = problem.b.segment(d * contacts[i], d);
    island.mu[i] = problem.mu[contacts[i]];
  }
  if (problem.storage == DelassusStorage::sparse) {
    std::vector<Eigen::Triplet<double>> entries;
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < d; ++k)
        for (SparseDelassus::InnerIterator it(problem.W_sparse, d * contacts[i] + k); it; ++it) {
          const int column = static_cast<int>(it.col());
          entries.emplace_back(d * i + k, d * local[column / d] + column % d, it.value());
        }
    SparseDelassus W(d * n, d * n);
    W.setFromTriplets(entries.begin(), entries.end());
    W.makeCompressed();
    if (storage == DelassusStorage::sparse) {
      island.W_sparse = std::move(W);
      island_body_blocks(problem, contacts, island);
    } else {
      island.W = Eigen::MatrixXd(W);
    }
    return island;
  }
  Eigen::MatrixXd W(d * n, d * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) W.block(d * i, d * j, d, d) = problem.W.block(d * contacts[i], d * contacts[j], d, d);
  if (storage == DelassusStorage::dense) {
    island.W = std::move(W);
  } else {
    island.W_sparse = W.sparseView(0.0, 0.0);  // not used by the steppers: a dense W is split dense
    island.W_sparse.makeCompressed();
  }
  return island;
}

void scatter_island(const std::vector<int>& contacts, int dimension, const Eigen::VectorXd& island_r,
                    const std::vector<ContactStatus>* island_status, Eigen::VectorXd& r,
                    std::vector<ContactStatus>* status) {
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    r.segment(dimension * contacts[i], dimension) = island_r.segment(dimension * i, dimension);
    if (status != nullptr && island_status != nullptr) (*status)[contacts[i]] = (*island_status)[i];
  }
}

Eigen::VectorXd gather_island(const std::vector<int>& contacts, int dimension, const Eigen::VectorXd& r) {
  Eigen::VectorXd island_r(dimension * static_cast<int>(contacts.size()));
  for (std::size_t i = 0; i < contacts.size(); ++i)
    island_r.segment(dimension * i, dimension) = r.segment(dimension * contacts[i], dimension);
  return island_r;
}

}  // namespace csim
