// Reading FCLib's HDF5 problem files. The file is one of Siconos' test problems
// (tests/contact/data/siconos/README.md), written by FCLib; the expected entries are the raw datasets
// /fclib_local/W/{p, i, x} (compressed rows), vectors/q and vectors/mu as HDF5's H5LTread_dataset_* gives
// them, printed with %.17g.
#include "contact/fclib_problem_format.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>

namespace csim {
namespace {

const std::string kData = CSIM_SOURCE_DIR "/tests/contact/data/siconos/";

void expect_close(double actual, double expected) {
  EXPECT_NEAR(actual, expected, 1e-15 * std::abs(expected)) << "expected " << expected;
}

TEST(FclibProblemFormat, CompressedRowsGiveSparseStorageInWholeBlocks) {
  const std::string path = kData + "LMGC_100_PR_PerioBox-i00361-60-03000.hdf5";
  ASSERT_TRUE(is_hdf5_file(path));
  const FrictionContactProblem problem = read_fclib_problem(path);
  EXPECT_EQ(problem.dimension, 3);
  EXPECT_EQ(problem.contacts, 60);
  EXPECT_EQ(problem.equalities, 0);
  ASSERT_EQ(problem.storage, DelassusStorage::sparse);
  EXPECT_EQ(inconsistency(problem), "");
  const SparseDelassus& W = problem.W_sparse;
  expect_close(W.coeff(0, 0), 1.0231321373347495e-05);
  expect_close(W.coeff(0, 1), 3.2981695103321087e-06);
  expect_close(W.coeff(1, 0), 3.2981695103321091e-06);
  expect_close(W.coeff(0, 90), 5.4089126424839446e-06);
  expect_close(W.coeff(1, 92), 2.7455448051693418e-06);
  expect_close(W.coeff(179, 177), -1.3046278122662879e-06);
  expect_close(W.coeff(179, 179), 1.2944839015776404e-05);
  expect_close(problem.b(0), -0.19619411795336042);
  expect_close(problem.b(179), 1.4019589753160157e-14);
  EXPECT_EQ(problem.mu[0], Eigen::Vector2d(0.5, 0.5));
  EXPECT_EQ(W.nonZeros() % 9, 0);  // whole 3 × 3 blocks
}

TEST(FclibProblemFormat, OtherFilesAreRefusedByName) {
  // A Siconos text file is no HDF5 file.
  const std::string text = kData + "Rover4396.dat";
  EXPECT_FALSE(is_hdf5_file(text));
  try {
    read_fclib_problem(text);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("cannot open as an HDF5 file"), std::string::npos) << error.what();
  }
  EXPECT_THROW(read_fclib_problem(kData + "no-such-file.hdf5"), std::runtime_error);
}

}  // namespace
}  // namespace csim
