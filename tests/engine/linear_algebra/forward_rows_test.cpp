// The forward columns stored by the factor's rows (engine/linear_algebra/forward_rows.h): their dots and w + Y r the same
// to the bit as SparseLdlt::dot and add_scaled column by column, with every column or a subset, and
// rebuilt when a row of the list changes.
#include "engine/linear_algebra/forward_rows.h"

#include "tests/engine/grid_stencil.h"

#include <gtest/gtest.h>

#include <cmath>

namespace csim {
namespace {

// Contact rows on nodes along one edge of the grid (two rows a node), in the cache; their slots.
std::vector<int> contact_slots(DelassusCache& cache, const SparseLdlt& factor, const std::vector<int>& nodes,
                               double slope) {
  cache.begin(factor);
  std::vector<int> slots;
  for (const int node : nodes)
    for (int k = 0; k < 2; ++k) {
      const int index[2] = {node, node + 1};
      const double value[2] = {1.0, k == 0 ? slope : -slope};
      slots.push_back(cache.slot({0, {0, 1, node}, k}, index, value, 2));
    }
  cache.finish();
  return slots;
}

Vector varied(int n, double phase) {
  Vector z(n);
  for (int i = 0; i < n; ++i) z(i) = std::sin(phase + 0.37 * i) * (1.0 + 1e-3 * i);
  return z;
}

void expect_dots(const ForwardRows& rows, const DelassusCache& cache, const std::vector<int>& slots,
                 const Vector& z) {
  std::vector<double> dots;
  rows.dots(z, dots);
  ASSERT_EQ(dots.size(), slots.size());
  for (std::size_t c = 0; c < slots.size(); ++c) EXPECT_EQ(dots[c], SparseLdlt::dot(cache.forward(slots[c]), z)) << c;
}

TEST(ForwardRows, DotsAndSumsAreTheColumnByColumnOnesToTheBit) {
  const SparseMatrix A = grid_stencil(14, 0.1);
  SparseLdlt factor;
  ASSERT_TRUE(factor.factor_positive_definite(A));
  DelassusCache cache;
  const std::vector<int> slots = contact_slots(cache, factor, {0, 14, 28, 42, 56, 70, 84}, 0.3);
  ForwardRows rows;
  rows.assign(cache, slots, factor.size());
  EXPECT_EQ(rows.columns(), 14);
  expect_dots(rows, cache, slots, varied(factor.size(), 0.2));

  std::vector<double> r(slots.size());
  for (std::size_t c = 0; c < r.size(); ++c) r[c] = 0.1 + 0.7 * std::cos(1.3 * c);
  for (const bool subset : {false, true}) {
    std::vector<char> use(slots.size(), 1);
    if (subset) use[0] = use[5] = use[13] = 0;  // contacts out of the problem: not added at all
    Vector expected = varied(factor.size(), 1.1), w = expected;
    for (std::size_t c = 0; c < slots.size(); ++c)
      if (use[c]) SparseLdlt::add_scaled(r[c], cache.forward(slots[c]), expected);
    rows.add(r, use, w);
    for (int i = 0; i < factor.size(); ++i) EXPECT_EQ(w(i), expected(i)) << (subset ? "subset " : "all ") << i;
  }
}

TEST(ForwardRows, ARowThatChangesIsStoredAgain) {
  const SparseMatrix A = grid_stencil(12, 0.1);
  SparseLdlt factor;
  ASSERT_TRUE(factor.factor_positive_definite(A));
  DelassusCache cache;
  ForwardRows rows;
  const Vector z = varied(factor.size(), 0.5);
  const std::vector<int> first = contact_slots(cache, factor, {0, 24, 48}, 0.2);
  rows.assign(cache, first, factor.size());
  expect_dots(rows, cache, first, z);
  // The same nodes on a steeper surface: the same keys and slots, new forward columns.
  const std::vector<int> second = contact_slots(cache, factor, {0, 24, 48}, 0.9);
  ASSERT_EQ(second, first);
  rows.assign(cache, second, factor.size());
  expect_dots(rows, cache, second, z);
  // And the same rows again: nothing to store, the same dots.
  rows.assign(cache, contact_slots(cache, factor, {0, 24, 48}, 0.9), factor.size());
  expect_dots(rows, cache, second, z);
}

}  // namespace
}  // namespace csim
