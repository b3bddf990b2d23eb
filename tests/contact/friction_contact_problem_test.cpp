// The plain-text dump of a FrictionContactProblem: exact round trip, and clear failures.
#include "contact/friction_contact_problem.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

namespace csim {
namespace {

// Bitwise equality, so that −0.0, NaN payload-free quiet NaNs and denormals all count.
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_identical(const FrictionContactProblem& a, const FrictionContactProblem& b) {
  EXPECT_EQ(a.dimension, b.dimension);
  EXPECT_EQ(a.contacts, b.contacts);
  EXPECT_EQ(a.equalities, b.equalities);
  ASSERT_EQ(a.W.rows(), b.W.rows());
  ASSERT_EQ(a.W.cols(), b.W.cols());
  ASSERT_EQ(a.b.size(), b.b.size());
  ASSERT_EQ(a.mu.size(), b.mu.size());
  for (Eigen::Index i = 0; i < a.W.size(); ++i)
    EXPECT_TRUE(same_bits(a.W(i), b.W(i))) << "W entry " << i << ": " << a.W(i) << " vs " << b.W(i);
  for (Eigen::Index i = 0; i < a.b.size(); ++i)
    EXPECT_TRUE(same_bits(a.b(i), b.b(i))) << "b entry " << i << ": " << a.b(i) << " vs " << b.b(i);
  for (std::size_t c = 0; c < a.mu.size(); ++c)
    for (int k = 0; k < 2; ++k) EXPECT_TRUE(same_bits(a.mu[c](k), b.mu[c](k))) << "mu " << c;
}

FrictionContactProblem random_problem(int dimension, int contacts, int equalities, unsigned seed) {
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  FrictionContactProblem problem;
  problem.dimension = dimension;
  problem.contacts = contacts;
  problem.equalities = equalities;
  const int n = problem.size();
  Eigen::MatrixXd A(n, n);
  for (Eigen::Index i = 0; i < A.size(); ++i) A(i) = entry(generator);
  problem.W = A * A.transpose();
  problem.b.resize(n);
  for (int i = 0; i < n; ++i) problem.b(i) = entry(generator) / 3.0;
  for (int c = 0; c < contacts; ++c)
    problem.mu.emplace_back(std::abs(entry(generator)), std::abs(entry(generator)));
  return problem;
}

FrictionContactProblem round_trip(const FrictionContactProblem& problem) {
  std::stringstream stream;
  write_problem(stream, problem);
  return read_problem(stream);
}

TEST(FrictionContactProblemIo, RoundTripIsExact) {
  const FrictionContactProblem problem = random_problem(3, 3, 2, 7);
  expect_identical(problem, round_trip(problem));
  const FrictionContactProblem plane = random_problem(2, 4, 0, 11);
  expect_identical(plane, round_trip(plane));
}

TEST(FrictionContactProblemIo, RoundTripKeepsAwkwardValues) {
  FrictionContactProblem problem = random_problem(2, 1, 1, 3);
  problem.W(0, 0) = 0.1;
  problem.W(0, 1) = -0.0;
  problem.W(1, 0) = std::numeric_limits<double>::denorm_min();
  problem.W(1, 1) = std::numeric_limits<double>::max();
  problem.W(2, 2) = 1.0 / 3.0;
  problem.b(0) = std::numeric_limits<double>::quiet_NaN();
  problem.b(1) = -std::numeric_limits<double>::infinity();
  problem.b(2) = std::nextafter(1.0, 2.0);
  problem.mu[0] = Eigen::Vector2d(0.3, 0.0);
  const FrictionContactProblem copy = round_trip(problem);
  expect_identical(problem, copy);
  EXPECT_TRUE(std::isnan(copy.b(0)));
}

TEST(FrictionContactProblemIo, EmptyProblemRoundTrips) {
  FrictionContactProblem problem;
  problem.W.resize(0, 0);
  problem.b.resize(0);
  expect_identical(problem, round_trip(problem));
}

TEST(FrictionContactProblemIo, FormatIsReadable) {
  FrictionContactProblem problem;
  problem.dimension = 2;
  problem.contacts = 1;
  problem.W = Eigen::Matrix2d::Identity();
  problem.b = Eigen::Vector2d(-0.1, 0.3);
  problem.mu = {Eigen::Vector2d(0.5, 0.0)};
  std::ostringstream out;
  write_problem(out, problem);
  EXPECT_EQ(out.str(),
            "csim-friction-contact-problem 1\n"
            "dimension 2\n"
            "contacts 1\n"
            "equalities 0\n"
            "mu\n"
            "0.5 0\n"
            "q\n"
            "-0.1 0.3\n"
            "W\n"
            "1 0\n"
            "0 1\n"
            "end\n");
}

// The message must say what is wrong, not merely that something is.
void expect_read_error(const std::string& text, const std::string& fragment) {
  std::istringstream in(text);
  try {
    read_problem(in);
    ADD_FAILURE() << "no exception for input:\n" << text;
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("read_problem"), std::string::npos) << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << "message '" << message << "' lacks '"
                                                         << fragment << "'";
  }
}

TEST(FrictionContactProblemIo, MalformedInputThrowsWithAMessage) {
  const std::string header = "csim-friction-contact-problem 1\ndimension 2\ncontacts 1\nequalities 0\n";
  const std::string valid = header + "mu\n0.5 0\nq\n-0.1 0.3\nW\n1 0\n0 1\nend\n";
  {
    std::istringstream in(valid);  // the reference text itself is accepted
    EXPECT_NO_THROW(read_problem(in));
  }
  expect_read_error("", "end of input");
  expect_read_error("friction-problem 1\n", "csim-friction-contact-problem");
  expect_read_error("csim-friction-contact-problem 2\n", "version 2");
  expect_read_error("csim-friction-contact-problem 1\ndimension 4\n", "dimension");
  expect_read_error("csim-friction-contact-problem 1\ndimension 3\ncontacts -1\nequalities 0\n",
                    "negative");
  expect_read_error("csim-friction-contact-problem 1\ndimension 3\ncontacts 1e9\n", "malformed integer");
  expect_read_error("csim-friction-contact-problem 1\ndimension 3\ncontacts 100000000\nequalities 0\n",
                    "exceeds");
  expect_read_error(header + "mu\n0.5 0\nq\n-0.1 0.3.2\n", "malformed number '0.3.2'");
  expect_read_error(header + "mu\n0.5 0\nq\n-0.1 0.3\nW\n1 0\n0\n", "end of input");
  expect_read_error(header + "mu\n0.5 0\nq\n-0.1 0.3\nW\n1 0\n0 1 7\nend\n", "'end'");
  expect_read_error(header + "friction\n0.5 0\n", "'mu'");
}

TEST(FrictionContactProblemIo, WritingAnInconsistentProblemThrows) {
  FrictionContactProblem problem = random_problem(3, 2, 0, 5);
  problem.b.resize(5);
  std::ostringstream out;
  EXPECT_THROW(write_problem(out, problem), std::runtime_error);
}

}  // namespace
}  // namespace csim
