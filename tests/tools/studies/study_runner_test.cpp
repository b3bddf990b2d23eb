// The serial study runner and the records it carries: every case once, reported in case order; a stop
// request ends the study between cases; a record reads back bit for bit (NaN, −0, denormals included).
#include "tools/run/stop_request.h"
#include "tools/studies/case_record.h"
#include "tools/studies/study_runner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <signal.h>

namespace csim {
namespace {

std::uint64_t bits(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

TEST(CaseRecord, ReadsBackWhatWasWrittenBitForBit) {
  const std::vector<double> numbers{std::numeric_limits<double>::quiet_NaN(), -0.0, 4.9e-324, 0.1 + 0.2, -1e308};
  RecordWriter out;
  out.text("moreau-jean").numbers(numbers).integer(-7).flag(true).texts({"a,b", "", "x\ny"}).number(1.0 / 3.0);
  RecordReader in(out.bytes());
  EXPECT_EQ(in.text(), "moreau-jean");
  const std::vector<double> back = in.numbers();
  ASSERT_EQ(back.size(), numbers.size());
  for (std::size_t k = 0; k < numbers.size(); ++k) EXPECT_EQ(bits(back[k]), bits(numbers[k])) << k;
  EXPECT_EQ(in.integer(), -7);
  EXPECT_TRUE(in.flag());
  EXPECT_EQ(in.texts(), (std::vector<std::string>{"a,b", "", "x\ny"}));
  EXPECT_EQ(bits(in.number()), bits(1.0 / 3.0));
  EXPECT_THROW(in.number(), std::runtime_error);  // past the end
}

TEST(CaseRecord, ACutRecordIsRefused) {
  RecordWriter out;
  out.text("a long enough text");
  const std::string cut = out.bytes().substr(0, out.bytes().size() - 3);
  RecordReader in(cut);
  EXPECT_THROW(in.text(), std::runtime_error);
}

TEST(SerialRunner, RunsEveryCaseOnceAndReportsThemInOrder) {
  std::vector<std::size_t> ran, reported;
  std::vector<std::string> records;
  serial_runner().run(
      5, [&](std::size_t i) { ran.push_back(i); return "case " + std::to_string(i); },
      [&](std::size_t i, const std::string& record) { reported.push_back(i); records.push_back(record); });
  EXPECT_EQ(ran, (std::vector<std::size_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(reported, ran);
  EXPECT_EQ(records.back(), "case 4");
  EXPECT_TRUE(serial_runner().is_root());
  EXPECT_FALSE(serial_runner().placement().mpi);
  EXPECT_EQ(serial_runner().placement().text(), "serial (1 process)");
  EXPECT_EQ(serial_runner().share("folder"), "folder");
}

TEST(SerialRunner, AStopRequestEndsTheStudyBetweenCases) {
  std::size_t ran = 0;
  auto run_case = [&](std::size_t i) {
    ++ran;
    if (i == 1) request_stop(SIGTERM);
    return std::string();
  };
  try {
    serial_runner().run(4, run_case, [](std::size_t, const std::string&) {});
    FAIL() << "no StopRequested";
  } catch (const StopRequested& stop) {
    EXPECT_EQ(stop.signal, SIGTERM);
  }
  clear_stop_request();
  EXPECT_EQ(ran, 2u);
}

TEST(Placement, SaysHowTheRanksWereBound) {
  Placement placement;
  placement.mpi = true;
  placement.ranks = 2;
  placement.binding = "rank 0 cpu 0; rank 1 cpu 1";
  EXPECT_EQ(placement.text(), "MPI, 2 ranks (rank 0 hands out the cases and runs some), binding rank 0 cpu 0; rank 1 cpu 1");
}

}  // namespace
}  // namespace csim
