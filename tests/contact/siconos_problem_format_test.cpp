// Reading Siconos' FrictionContactProblem text format. The files are Siconos' own test problems
// (tests/contact/data/siconos/README.md); the expected entries are those that Siconos 4.4's reader
// (frictionContact_newFromFile) and NM_get_value give for the same files, printed with %.17g, so a
// transposed block, a shifted index or a lost digit shows.
#include "contact/siconos_problem_format.h"
#include "tests/contact/test_problems.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

namespace csim {
namespace {

// Entry (i, j) of W whichever storage holds it.
double entry(const FrictionContactProblem& problem, int i, int j) {
  return problem.storage == DelassusStorage::dense ? problem.W(i, j) : problem.W_sparse.coeff(i, j);
}

// Decimal values printed with 17 digits read back to within one ulp or so.
void expect_close(double actual, double expected) {
  EXPECT_NEAR(actual, expected, 1e-15 * std::abs(expected)) << "expected " << expected;
}

// Every stored entry of W_sparse lies in a d × d block all of whose entries are stored.
void expect_whole_blocks(const FrictionContactProblem& problem) {
  const int d = problem.dimension;
  const SparseDelassus& W = problem.W_sparse;
  for (int row = 0; row < W.rows(); ++row)
    for (SparseDelassus::InnerIterator it(W, row); it; ++it) {
      const int block_row = row / d * d, block_column = static_cast<int>(it.col()) / d * d;
      for (int i = 0; i < d; ++i) {
        const int stored_row = block_row + i;
        int stored = 0;
        for (SparseDelassus::InnerIterator other(W, stored_row); other; ++other)
          if (other.col() >= block_column && other.col() < block_column + d) ++stored;
        EXPECT_EQ(stored, d) << "block (" << block_row / d << ", " << block_column / d << ") row " << i;
      }
    }
}

TEST(SiconosProblemFormat, DenseIsColumnMajor) {
  const FrictionContactProblem problem = test::siconos_file("Rover4396.dat");
  EXPECT_EQ(problem.dimension, 3);
  EXPECT_EQ(problem.contacts, 2);
  EXPECT_EQ(problem.equalities, 0);
  ASSERT_EQ(problem.storage, DelassusStorage::dense);
  ASSERT_EQ(problem.W.rows(), 6);
  EXPECT_EQ(inconsistency(problem), "");
  expect_close(problem.W(0, 0), 0.012062654401707928);
  expect_close(problem.W(0, 1), -0.000154335100640024);  // the second line's first number
  expect_close(problem.W(1, 0), -0.00015159880375974319);  // the first line's second number
  expect_close(problem.W(0, 5), -2.10561955731642e-05);
  expect_close(problem.b(0), -7.993436691636901514357305e-02);
  expect_close(problem.b(5), -2.339750149624925779079376e+00);
  ASSERT_EQ(problem.mu.size(), 2u);
  EXPECT_EQ(problem.mu[1](0), problem.mu[1](1));  // Siconos' cone is isotropic
  expect_close(problem.mu[1](0), 0.7);
}

TEST(SiconosProblemFormat, TwoDimensionalDenseUnsymmetric) {
  const FrictionContactProblem problem = test::siconos_file("FC2D_SliderCrankLagrangian00000.dat");
  EXPECT_EQ(problem.dimension, 2);
  EXPECT_EQ(problem.contacts, 2);
  ASSERT_EQ(problem.storage, DelassusStorage::dense);
  expect_close(problem.W(0, 1), -464.2662921766746);
  expect_close(problem.W(1, 0), -464.2665883420583);
  expect_close(problem.W(2, 3), 461.6596337492515);
  expect_close(problem.W(3, 2), 461.6593375838678);
  expect_close(problem.mu[0](0), 0.01);
}

// An older writer put blank lines between the items: whitespace is free, as for fscanf.
TEST(SiconosProblemFormat, OneContactWithBlankLines) {
  const FrictionContactProblem problem = test::siconos_file("FrictionContact3D_1c.dat");
  Eigen::Matrix3d W;
  W << 15, -1, -2, -1, 14, 1, -2, 1, 16;
  EXPECT_EQ(problem.W, Eigen::MatrixXd(W));
  EXPECT_EQ(problem.b, Eigen::Vector3d(-1, 2, 3));
  EXPECT_EQ(problem.mu[0](0), 0.1);
}

TEST(SiconosProblemFormat, SparseBlockGivesSparseStorage) {
  const FrictionContactProblem problem = test::siconos_file("Confeti-ex13-4contact-Fc3D-SBM.dat");
  EXPECT_EQ(problem.contacts, 4);
  ASSERT_EQ(problem.storage, DelassusStorage::sparse);
  EXPECT_EQ(problem.W.size(), 0);
  EXPECT_EQ(inconsistency(problem), "");
  EXPECT_EQ(problem.W_sparse.nonZeros(), 144);  // all 16 blocks stored
  expect_close(entry(problem, 0, 1), -1.7680060000000001e-05);
  expect_close(entry(problem, 0, 3), -4.8202180000000001e-06);
  expect_close(entry(problem, 5, 11), -6.5633889999999996e-06);
  expect_close(entry(problem, 10, 2), 8.5594199999999994e-06);
  expect_close(problem.b(11), 0.41099990478078197);
  expect_close(problem.mu[3](0), 0.04);
  expect_whole_blocks(problem);
}

// FC2D, diagonal blocks only, whose off-diagonal entries differ in sign: a transposed block shows.
TEST(SiconosProblemFormat, SparseBlockTwoDimensionalKeepsBlockOrientation) {
  const FrictionContactProblem problem = test::siconos_file("FrictionContactProblem00031.dat");
  EXPECT_EQ(problem.dimension, 2);
  EXPECT_EQ(problem.contacts, 11);
  ASSERT_EQ(problem.storage, DelassusStorage::sparse);
  expect_close(entry(problem, 0, 0), 0.44359199999999999);
  expect_close(entry(problem, 0, 1), -1.084202e-18);
  expect_close(entry(problem, 1, 0), 1.084202e-18);
  expect_close(entry(problem, 3, 2), -6.315478e-18);
  expect_close(entry(problem, 5, 5), 1.334497);
  expect_close(problem.b(21), 2.2416497250728369e-07);
  expect_close(problem.mu[10](0), 0.9);
  expect_whole_blocks(problem);
}

TEST(SiconosProblemFormat, DenseAndSparseBlockFilesOfOneProblemAgree) {
  const FrictionContactProblem dense = test::siconos_file("FC3D_Example1.dat");
  const FrictionContactProblem blocks = test::siconos_file("FC3D_Example1_SBM.dat");
  ASSERT_EQ(blocks.storage, DelassusStorage::sparse);
  EXPECT_EQ(Eigen::MatrixXd(blocks.W_sparse), dense.W);
  EXPECT_EQ(blocks.b, dense.b);
  EXPECT_EQ(blocks.mu, dense.mu);
}

// CSparse's compressed columns (granular flow in 2D, 667 contacts), completed to whole 2 × 2 blocks.
TEST(SiconosProblemFormat, CompressedColumnsGiveSparseStorageInWholeBlocks) {
  const FrictionContactProblem problem = test::siconos_file("fc2d_granularflowonwall_00667_00000.dat");
  EXPECT_EQ(problem.dimension, 2);
  EXPECT_EQ(problem.contacts, 667);
  ASSERT_EQ(problem.storage, DelassusStorage::sparse);
  EXPECT_EQ(inconsistency(problem), "");
  expect_close(entry(problem, 0, 0), 856.713);
  expect_close(entry(problem, 649, 0), -454.43);
  expect_close(entry(problem, 0, 649), -454.43);
  expect_close(entry(problem, 1, 648), 454.43);
  EXPECT_EQ(entry(problem, 0, 648), 0.0);  // stored as the zero that completes block (0, 324)
  EXPECT_EQ(problem.b(1333), 0.0);
  EXPECT_EQ(problem.mu[666](0), 0.5);
  EXPECT_EQ(problem.W_sparse.nonZeros() % 4, 0);
  expect_whole_blocks(problem);
}

// The line of the offending token, and what was wrong with it.
void expect_error(const std::string& text, int line, const std::string& part) {
  std::istringstream in(text);
  try {
    read_siconos_problem(in);
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const ProblemFileError& error) {
    EXPECT_EQ(error.line(), line) << error.what();
    EXPECT_NE(std::string(error.what()).find(part), std::string::npos) << error.what();
  }
}

TEST(SiconosProblemFormat, MalformedInputNamesTheLine) {
  const std::string header = "3\n1\n0\n3\n3\n3\t3\n";
  const std::string W = "1 0 0\n0 1 0\n0 0 1\n";
  expect_error("", 1, "end of input");
  expect_error("4\n1\n", 1, "dimension");
  expect_error("3\n1\n5\n3\n3\n", 3, "storage");
  expect_error("3\n2\n0\n3\n3\n", 4, "row count");
  expect_error(header + W + "1 2\n", 10, "end of input while reading q");
  expect_error(header + "1 0 0\n0 x 0\n0 0 1\n-1 0 0\n0.3\n", 8, "malformed number 'x'");
  expect_error(header + W + "1 nan 0\n0.3\n", 10, "non-finite");
  expect_error(header + W + "-1 0 0\n-0.3\n", 11, "negative friction");
  // One token after mu is a flag some of Siconos' files end with; more is another kind of file.
  {
    std::istringstream flagged(header + W + "-1 0 0\n0.3\n1\n");
    EXPECT_NO_THROW(read_siconos_problem(flagged));
  }
  expect_error(header + W + "-1 0 0\n0.3\n3\n1.0 0.0\n", 13, "more after mu");
  // A block row of 4 rows in a dimension-3 problem splits a contact.
  expect_error("3\n2\n1\n6\n6\n1\n1\n1\n4\t6\n", 9, "splits a contact");
  // A block numbered out of order.
  expect_error("3\n1\n1\n3\n3\n1\n1\n1\n3\n3\n2\n1\n0 1\n0\n7\n", 15, "block's number");
}

}  // namespace
}  // namespace csim
