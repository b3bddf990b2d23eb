// The Delassus cache of a sparse linear World (engine/contact_stage/delassus_cache.h): W of the rows asked for against
// H A⁻¹ Hᵀ from dense algebra as contacts enter, stay, change their row and leave, only the new rows'
// entries computed, and everything dropped on a refactorization.
#include "engine/contact_stage/delassus_cache.h"

#include "tests/engine/grid_stencil.h"

#include <gtest/gtest.h>

namespace csim {
namespace {

struct Row {
  DelassusCache::Key key;
  std::vector<int> index;
  std::vector<double> value;
};

Row contact_row(int node, int k, double slope) {
  return {{0, {0, 1, node}, k}, {node, node + 1}, {1.0, k == 0 ? slope : -slope}};
}

// W through the cache for these rows against the dense product; the rows' slots.
std::vector<int> expect_delassus(DelassusCache& cache, const SparseLdlt& factor, const SparseMatrix& A,
                     const std::vector<Row>& rows) {
  cache.begin(factor);
  std::vector<int> slots;
  for (const Row& row : rows)
    slots.push_back(cache.slot(row.key, row.index.data(), row.value.data(), static_cast<int>(row.index.size())));
  cache.finish();
  cache.compute_entries();
  const int m = static_cast<int>(rows.size()), n = static_cast<int>(A.rows());
  Matrix H = Matrix::Zero(m, n);
  for (int a = 0; a < m; ++a)
    for (std::size_t k = 0; k < rows[a].index.size(); ++k) H(a, rows[a].index[k]) = rows[a].value[k];
  const Matrix expected = H * Matrix(A).ldlt().solve(H.transpose());
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b) {
      EXPECT_NEAR(cache(slots[a], slots[b]), expected(a, b), 1e-12 * expected.lpNorm<Eigen::Infinity>());
      EXPECT_EQ(cache(slots[a], slots[b]), cache(slots[b], slots[a]));
    }
  EXPECT_EQ(cache.rows(), rows.size());
  return slots;
}

// A grid stencil's matrix A (size × size nodes), its factor and an empty cache.
struct FactoredGrid {
  explicit FactoredGrid(int size) : A(grid_stencil(size, 0.1)) { positive_definite = factor.factor_positive_definite(A); }
  SparseMatrix A;
  SparseLdlt factor;
  DelassusCache cache;
  bool positive_definite = false;
};

// Two rows of one node's contact and one row of another's.
std::vector<Row> three_rows() { return {contact_row(3, 0, 0.2), contact_row(3, 1, 0.2), contact_row(40, 0, 0.5)}; }

// A user of the forward columns alone (a sparse W, block_gram.h) holds no dense W: slots × slots doubles
// would be 290 MB for the 3000 rows of 1000 dropped spheres. Asked for entries, the cache then stores them.
TEST(DelassusCache, HoldsNoDenseEntriesUntilTheyAreAskedFor) {
  FactoredGrid grid(10);
  ASSERT_TRUE(grid.positive_definite);
  std::vector<Row> rows;
  for (int node = 0; node < 60; node += 2) rows.push_back(contact_row(node, 0, 0.1));
  grid.cache.begin(grid.factor);
  for (const Row& row : rows) grid.cache.slot(row.key, row.index.data(), row.value.data(), static_cast<int>(row.index.size()));
  grid.cache.finish();
  EXPECT_EQ(grid.cache.rows(), rows.size());
  EXPECT_EQ(grid.cache.dense_capacity(), 0);
  expect_delassus(grid.cache, grid.factor, grid.A, rows);
  EXPECT_GE(grid.cache.dense_capacity(), static_cast<Eigen::Index>(rows.size()));
}

TEST(DelassusCache, KeepsTheEntriesOfRowsThatStayAndComputesThoseOfRowsThatEnter) {
  FactoredGrid grid(10);
  ASSERT_TRUE(grid.positive_definite);
  auto& [A, factor, cache, positive_definite] = grid;
  std::vector<Row> rows = three_rows();
  expect_delassus(cache, factor, A, rows);
  EXPECT_EQ(cache.computed_entries(), 6);  // the 3 × 3 triangle
  expect_delassus(cache, factor, A, rows);  // nothing new
  EXPECT_EQ(cache.computed_entries(), 6);
  rows.push_back(contact_row(77, 0, 0.1));  // a contact enters: one row against four
  expect_delassus(cache, factor, A, rows);
  EXPECT_EQ(cache.computed_entries(), 10);
  rows.erase(rows.begin());  // one leaves, another's row changes (a node sliding onto a slope)
  rows[1] = contact_row(40, 0, 0.7);
  expect_delassus(cache, factor, A, rows);
  EXPECT_EQ(cache.computed_entries(), 13);
  rows.push_back(contact_row(3, 0, 0.2));  // back: into the freed slot, its entries computed again
  rows.push_back(contact_row(90, 1, 0.3));
  expect_delassus(cache, factor, A, rows);
  EXPECT_EQ(cache.computed_entries(), 13 + 4 + 5);
}

TEST(DelassusCache, DropsEverythingWhenTheFactorIsRefactored) {
  FactoredGrid grid(6);
  ASSERT_TRUE(grid.positive_definite);
  auto& [A, factor, cache, positive_definite] = grid;
  const std::vector<Row> rows = {contact_row(2, 0, 0.2), contact_row(20, 1, 0.4)};
  expect_delassus(cache, factor, A, rows);
  A = 2.0 * A;
  ASSERT_TRUE(factor.factor_positive_definite(A));
  expect_delassus(cache, factor, A, rows);  // the new A's entries, not the kept ones
  EXPECT_EQ(cache.computed_entries(), 6);
}

// What a user took for a list of slots holds while the slots are the same and no row was computed again.
TEST(DelassusCache, TakenSlotsHoldUntilTheListOrARowChanges) {
  FactoredGrid grid(8);
  ASSERT_TRUE(grid.positive_definite);
  auto& [A, factor, cache, positive_definite] = grid;
  std::vector<Row> rows = three_rows();
  const std::vector<int> slots = expect_delassus(cache, factor, A, rows);
  DelassusCache::Taken taken;
  EXPECT_FALSE(cache.still_holds(taken, slots));  // nothing taken yet: taken now
  EXPECT_TRUE(cache.still_holds(taken, slots));
  EXPECT_EQ(expect_delassus(cache, factor, A, rows), slots);  // the same rows: nothing computed
  EXPECT_TRUE(cache.still_holds(taken, slots));
  rows[2] = contact_row(40, 0, 0.9);  // the same key and slot, a new row
  EXPECT_EQ(expect_delassus(cache, factor, A, rows), slots);
  EXPECT_FALSE(cache.still_holds(taken, slots));
  EXPECT_TRUE(cache.still_holds(taken, slots));
  EXPECT_FALSE(cache.still_holds(taken, {slots[0], slots[1]}));  // another list
}

}  // namespace
}  // namespace csim
