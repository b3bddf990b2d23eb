// The fixed-pattern assembly of the Newton steppers' tangent (engine/linear_algebra/sparse_assembly.h): the matrix it
// assembles equals setFromTriplets' bit for bit, on its first assembly, on the next ones (values
// scattered into the remembered pattern), and after the positions change (an entry more, one less, one
// moved), and it builds the pattern again only then.
#include "engine/linear_algebra/sparse_assembly.h"

#include <gtest/gtest.h>

#include <random>

namespace csim {
namespace {

// Random entries on a few positions, many of them repeated (an element mesh's shared nodes), with
// values of mixed magnitudes so that the order of summation shows in the last bits.
Triplets random_entries(int n, int count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> index(0, n - 1);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Triplets entries;
  for (int k = 0; k < count; ++k) {
    const double scale = k % 3 == 0 ? 1e8 : k % 3 == 1 ? 1.0 : 1e-8;
    entries.emplace_back(index(random), index(random), scale * value(random));
  }
  return entries;
}

// Bitwise: the same pattern and the same value bits.
void expect_identical(const SparseMatrix& actual, const SparseMatrix& expected) {
  ASSERT_EQ(actual.rows(), expected.rows());
  ASSERT_EQ(actual.cols(), expected.cols());
  ASSERT_EQ(actual.nonZeros(), expected.nonZeros());
  ASSERT_TRUE(actual.isCompressed());
  for (int j = 0; j <= expected.cols(); ++j) ASSERT_EQ(actual.outerIndexPtr()[j], expected.outerIndexPtr()[j]) << j;
  for (int p = 0; p < expected.nonZeros(); ++p) {
    ASSERT_EQ(actual.innerIndexPtr()[p], expected.innerIndexPtr()[p]) << p;
    ASSERT_EQ(actual.valuePtr()[p], expected.valuePtr()[p]) << p;
  }
}

SparseMatrix from_triplets(int rows, int columns, const Triplets& entries) {
  SparseMatrix matrix(rows, columns);
  matrix.setFromTriplets(entries.begin(), entries.end());
  return matrix;
}

SparseMatrix assemble(SparseAssembly& assembly, int rows, int columns, const Triplets& entries, bool* rebuilt) {
  SparseMatrix matrix;
  assembly.begin();
  assembly.add(entries);
  *rebuilt = assembly.finish(rows, columns, matrix);
  return matrix;
}

TEST(SparseAssembly, EqualsSetFromTripletsBitForBitAcrossAssemblies) {
  const int n = 30;
  const Triplets first = random_entries(n, 2000, 1);
  SparseAssembly assembly;
  SparseMatrix matrix;
  for (int round = 0; round < 4; ++round) {
    Triplets entries = first;  // the same positions, new values
    std::mt19937 random(100 + round);
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    for (auto& e : entries) e = Eigen::Triplet<double>(e.row(), e.col(), e.value() * value(random));
    assembly.begin();
    for (const auto& e : entries) assembly.add(e.row(), e.col(), e.value());
    const bool rebuilt = assembly.finish(n, n, matrix);  // the same matrix object: its storage is kept
    EXPECT_EQ(rebuilt, round == 0);
    expect_identical(matrix, from_triplets(n, n, entries));
  }
  EXPECT_EQ(assembly.patterns(), 1);
}

TEST(SparseAssembly, BuildsThePatternAgainWhenThePositionsChange) {
  const int n = 20;
  const Triplets base = random_entries(n, 500, 2);
  SparseAssembly assembly;
  bool rebuilt = false;
  expect_identical(assemble(assembly, n, n, base, &rebuilt), from_triplets(n, n, base));
  // One more entry (a contact coupling two nodes not coupled yet), at the end and in the middle.
  Triplets more = base;
  more.emplace_back(0, n - 1, 3.0);
  expect_identical(assemble(assembly, n, n, more, &rebuilt), from_triplets(n, n, more));
  EXPECT_TRUE(rebuilt);
  more.insert(more.begin() + 250, Eigen::Triplet<double>(n - 1, 0, -2.0));
  expect_identical(assemble(assembly, n, n, more, &rebuilt), from_triplets(n, n, more));
  EXPECT_TRUE(rebuilt);
  expect_identical(assemble(assembly, n, n, more, &rebuilt), from_triplets(n, n, more));
  EXPECT_FALSE(rebuilt);
  // One entry less, and one moved.
  Triplets fewer = base;
  fewer.pop_back();
  expect_identical(assemble(assembly, n, n, fewer, &rebuilt), from_triplets(n, n, fewer));
  EXPECT_TRUE(rebuilt);
  Triplets moved = fewer;
  moved[10] = Eigen::Triplet<double>((moved[10].row() + 1) % n, moved[10].col(), moved[10].value());
  expect_identical(assemble(assembly, n, n, moved, &rebuilt), from_triplets(n, n, moved));
  EXPECT_TRUE(rebuilt);
  // Another size with the same entries.
  expect_identical(assemble(assembly, n + 5, n + 2, moved, &rebuilt), from_triplets(n + 5, n + 2, moved));
  EXPECT_TRUE(rebuilt);
  EXPECT_EQ(assembly.patterns(), 6);
}

// A matrix whose pattern the caller changed in between gets the assembly's pattern back.
TEST(SparseAssembly, RestoresAPatternTheCallerChanged) {
  const int n = 10;
  const Triplets entries = random_entries(n, 100, 3);
  SparseAssembly assembly;
  SparseMatrix matrix;
  assembly.begin();
  assembly.add(entries);
  assembly.finish(n, n, matrix);
  matrix.coeffRef(0, 0) += 1.0;  // may insert an entry
  matrix.coeffRef(n - 1, 0) += 1.0;
  matrix.makeCompressed();
  assembly.begin();
  assembly.add(entries);
  EXPECT_FALSE(assembly.finish(n, n, matrix));
  expect_identical(matrix, from_triplets(n, n, entries));
}

// The stream's head summed by the caller into the last pattern's slots (resume), as ReducedCoordinates
// does with a tangent's frame entries: the same bits as every entry added, with the tail repeating, with
// an entry more in the tail (the pattern built again keeps the head's sums), and with the tail shorter.
TEST(SparseAssembly, ResumeAfterAHeadSummedByTheCaller) {
  const int n = 20;
  const Triplets head = random_entries(n, 400, 4);
  Triplets tail = random_entries(n, 100, 5);
  SparseAssembly assembly;
  SparseMatrix matrix;
  assembly.begin();
  assembly.add(head);
  assembly.add(tail);
  assembly.finish(n, n, matrix);
  auto resumed = [&](const Triplets& new_tail, double scale, bool* rebuilt) {
    Triplets entries = head;
    for (auto& e : entries) e = Eigen::Triplet<double>(e.row(), e.col(), scale * e.value());
    std::vector<double> sums(assembly.nonzeros(), 0.0);
    for (std::size_t k = 0; k < entries.size(); ++k) sums[assembly.slot(k)] += entries[k].value();
    assembly.begin();
    assembly.resume(entries.size(), sums);
    assembly.add(new_tail);
    *rebuilt = assembly.finish(n, n, matrix);
    entries.insert(entries.end(), new_tail.begin(), new_tail.end());
    return from_triplets(n, n, entries);
  };
  bool rebuilt = true;
  expect_identical(matrix, resumed(tail, 0.5, &rebuilt));
  EXPECT_FALSE(rebuilt);
  tail.emplace_back(n - 1, 0, 7.0);
  tail.emplace_back(0, n - 1, -7.0);
  expect_identical(matrix, resumed(tail, 3.0, &rebuilt));
  EXPECT_TRUE(rebuilt);
  tail.resize(10);
  expect_identical(matrix, resumed(tail, -2.0, &rebuilt));
  EXPECT_TRUE(rebuilt);
  expect_identical(matrix, resumed(tail, 1.5, &rebuilt));
  EXPECT_FALSE(rebuilt);
  EXPECT_EQ(assembly.patterns(), 3);
}

TEST(SparseAssembly, EmptyStream) {
  SparseAssembly assembly;
  SparseMatrix matrix;
  assembly.begin();
  assembly.finish(4, 4, matrix);
  EXPECT_EQ(matrix.rows(), 4);
  EXPECT_EQ(matrix.nonZeros(), 0);
}

}  // namespace
}  // namespace csim
