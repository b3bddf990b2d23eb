// Islands of the contact problem (contact/islands.h) and their solve (engine/contact_stage/contact_solve.h):
// a problem made of three independent ones (180 rows), their contacts interleaved, splits into exactly those three
// (W stored dense or sparse), each island's sub-problem is the original one, and solve_contacts' answer
// meets the whole problem's tolerance and agrees with each problem solved alone.
#include "contact/islands.h"
#include "contact/pgs_solver.h"
#include "engine/contact_stage/contact_solve.h"

#include <gtest/gtest.h>

#include <random>

namespace csim {
namespace {

constexpr int kD = 3;

// A frictional problem of `contacts` 3D contacts: W = A Aᵀ + 0.1 I (symmetric positive definite), b with
// approaching normal velocities (every contact closes), μ = 0.5.
FrictionContactProblem random_problem(int contacts, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  FrictionContactProblem p;
  p.dimension = kD;
  p.contacts = contacts;
  const int m = kD * contacts;
  Eigen::MatrixXd A(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) A(i, j) = uniform(random);
  p.W = A * A.transpose() + 0.1 * Eigen::MatrixXd::Identity(m, m);
  p.b.resize(m);
  for (int c = 0; c < contacts; ++c) {
    p.b(kD * c) = -1.0 - 0.5 * (uniform(random) + 1.0);
    p.b(kD * c + 1) = uniform(random);
    p.b(kD * c + 2) = uniform(random);
  }
  p.mu.assign(contacts, Eigen::Vector2d(0.5, 0.5));
  return p;
}

// The three problems' contacts interleaved: `owner[c]` = (problem, its contact) of contact c.
struct Interleaved {
  std::vector<FrictionContactProblem> parts;
  std::vector<std::pair<int, int>> owner;
  FrictionContactProblem whole;
};

// 20 contacts each, dealt in turn (contact c of the whole is contact c / 3 of problem c % 3): 180 rows,
// above the size from which solve_contacts looks for islands (contact_solve.h).
constexpr int kPerPart = 20;

Interleaved interleaved(DelassusStorage storage) {
  Interleaved x;
  x.parts = {random_problem(kPerPart, 1), random_problem(kPerPart, 2), random_problem(kPerPart, 3)};
  for (int c = 0; c < 3 * kPerPart; ++c) x.owner.emplace_back(c % 3, c / 3);
  const int n = static_cast<int>(x.owner.size());
  FrictionContactProblem& w = x.whole;
  w.dimension = kD;
  w.contacts = n;
  w.W = Eigen::MatrixXd::Zero(kD * n, kD * n);
  w.b.resize(kD * n);
  w.mu.resize(n);
  for (int a = 0; a < n; ++a) {
    const auto [pa, ca] = x.owner[a];
    w.b.segment(kD * a, kD) = x.parts[pa].b.segment(kD * ca, kD);
    w.mu[a] = x.parts[pa].mu[ca];
    for (int b = 0; b < n; ++b) {
      const auto [pb, cb] = x.owner[b];
      if (pa == pb) w.W.block(kD * a, kD * b, kD, kD) = x.parts[pa].W.block(kD * ca, kD * cb, kD, kD);
    }
  }
  if (storage == DelassusStorage::sparse) {
    w.storage = storage;
    w.W_sparse = w.W.sparseView(0.0, 0.0);
    w.W_sparse.makeCompressed();
    w.W.resize(0, 0);
  }
  return x;
}

TEST(ContactIslands, ThreeInterleavedProblemsAreThreeIslands) {
  for (const DelassusStorage storage : {DelassusStorage::dense, DelassusStorage::sparse}) {
    SCOPED_TRACE(storage == DelassusStorage::dense ? "dense" : "sparse");
    const Interleaved x = interleaved(storage);
    const std::vector<std::vector<int>> islands = find_islands(x.whole);
    ASSERT_EQ(islands.size(), 3u);
    for (int i = 0; i < 3; ++i) {
      std::vector<int> expected;
      for (int c = i; c < 3 * kPerPart; c += 3) expected.push_back(c);
      EXPECT_EQ(islands[i], expected);
    }
    for (int i = 0; i < 3; ++i) {  // each island's problem is the original one, in either storage
      for (const DelassusStorage as : {DelassusStorage::dense, DelassusStorage::sparse}) {
        const FrictionContactProblem island = island_problem(x.whole, islands[i], as);
        const Eigen::MatrixXd W = as == DelassusStorage::dense ? island.W : Eigen::MatrixXd(island.W_sparse);
        EXPECT_EQ(W, x.parts[i].W);
        EXPECT_EQ(island.b, x.parts[i].b);
        EXPECT_EQ(island.mu, x.parts[i].mu);
      }
    }
  }
}

TEST(ContactIslands, EqualityRowsMakeOneIsland) {
  Interleaved x = interleaved(DelassusStorage::dense);
  FrictionContactProblem& w = x.whole;
  const int m = w.size();
  w.equalities = 1;
  w.W.conservativeResize(m + 1, m + 1);
  w.W.row(m).setZero();
  w.W.col(m).setZero();
  w.W(m, m) = 1.0;
  w.b.conservativeResize(m + 1);
  w.b(m) = 0.0;
  const auto islands = find_islands(w);
  ASSERT_EQ(islands.size(), 1u);
  EXPECT_EQ(islands[0].size(), static_cast<std::size_t>(3 * kPerPart));
}

TEST(ContactIslands, SolvedByIslandsMeetsTheWholeToleranceAndEachProblemAlone) {
  const double tolerance = 1e-10;
  const PgsSolver solver(PgsParameters{.max_iterations = 20000, .tolerance = tolerance});
  for (const DelassusStorage storage : {DelassusStorage::dense, DelassusStorage::sparse}) {
    SCOPED_TRACE(storage == DelassusStorage::dense ? "dense" : "sparse");
    const Interleaved x = interleaved(storage);
    Vector r = Vector::Zero(x.whole.size());
    std::vector<ActiveContact> active(x.whole.contacts);
    SolverCounters counters;
    const std::string failure = solve_contacts(solver, x.whole, 1e-6, 0.1, r, active, counters);
    EXPECT_EQ(failure, "");
    EXPECT_EQ(counters.not_converged, 0);
    EXPECT_LE(PgsSolver::residual(x.whole, r), tolerance);
    for (int p = 0; p < 3; ++p) {  // each problem alone, to the same tolerance: the same impulses
      Vector alone = Vector::Zero(x.parts[p].size());
      ASSERT_TRUE(solver.solve(x.parts[p], alone).converged);
      for (int c = 0; c < x.whole.contacts; ++c) {
        if (x.owner[c].first != p) continue;
        const Eigen::Vector3d mine = r.segment(kD * c, kD), theirs = alone.segment(kD * x.owner[c].second, kD);
        EXPECT_LE((mine - theirs).norm(), 1e-8 * theirs.norm()) << "contact " << c;
        EXPECT_EQ(active[c].impulse, mine);
      }
    }
  }
}

}  // namespace
}  // namespace csim
