// The work-precision study on the SDNV104 shoe: Moreau–Jean's error falls with the step, the CSV has
// one row per configuration with a full set of columns, bad options are rejected before any run, and
// an integrator that cannot run gives a failed row, not an exception.
#include "tools/studies/compare.h"
#include "tools/scene/scene_error.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace csim {
namespace {

CompareOptions shoe_study() {
  CompareOptions options;
  options.scene_file = std::string(CSIM_SOURCE_DIR) + "/scenes/sdnv104-rigid/scene.yaml";
  options.integrators = {"moreau-jean"};
  options.steps = {1e-2, 1e-3};
  options.repeats = 1;
  return options;
}

// Splits a CSV line into fields, honouring quoted fields (failure messages may hold commas).
std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '"' && quoted && i + 1 < line.size() && line[i + 1] == '"') {
      fields.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

TEST(Compare, MoreauJeanErrorFallsWithTheStep) {
  const Comparison comparison = run_comparison(shoe_study());
  EXPECT_EQ(comparison.scene_name, "sdnv104-rigid");
  ASSERT_FALSE(comparison.checks.empty());
  ASSERT_EQ(comparison.rows.size(), 2u);
  for (const CompareRow& row : comparison.rows) {
    EXPECT_TRUE(row.ok) << row.failure;
    EXPECT_EQ(row.integrator, "moreau-jean");
    EXPECT_EQ(row.parameter, "time.step");
    EXPECT_EQ(row.wall_times.size(), 1u);
    EXPECT_GT(row.wall_time_median, 0.0);
    EXPECT_EQ(row.errors.size(), comparison.checks.size());
    EXPECT_TRUE(std::isfinite(row.max_rel_error));
  }
  EXPECT_EQ(comparison.rows[0].steps, 1000);
  EXPECT_EQ(comparison.rows[1].steps, 10000);
  EXPECT_LT(comparison.rows[1].max_rel_error, comparison.rows[0].max_rel_error);
  EXPECT_TRUE(comparison.all_ok());
}

TEST(Compare, CsvHasAHeaderAndOneFullRowPerConfiguration) {
  const Comparison comparison = run_comparison(shoe_study());
  const std::filesystem::path directory =
      std::filesystem::temp_directory_path() / ("csim-compare-test-" + std::to_string(::getpid()));
  write_work_precision_csv(comparison, directory.string());
  std::ifstream in(directory / "work_precision.csv");
  ASSERT_TRUE(in);
  std::vector<std::vector<std::string>> lines;
  int comments = 0;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] == '#') ++comments;
    else lines.push_back(csv_fields(line));
  }
  std::filesystem::remove_all(directory);
  EXPECT_GT(comments, 0);
  ASSERT_EQ(lines.size(), 3u);  // header + 2 rows
  const std::size_t columns = 9 + 2 * comparison.checks.size();
  EXPECT_EQ(lines[0].size(), columns);
  EXPECT_EQ(lines[0][0], "integrator");
  EXPECT_EQ(lines[0][8], "max_rel_error");
  for (std::size_t r = 1; r < lines.size(); ++r) {
    EXPECT_EQ(lines[r].size(), columns);
    EXPECT_EQ(lines[r][7], "ok");
  }
}

TEST(Compare, UnknownIntegratorIsBadInput) {
  CompareOptions options = shoe_study();
  options.integrators = {"moreau-jean", "runge-kutta"};
  EXPECT_THROW(run_comparison(options), SceneError);
  options.integrators = {"moreau-jean"};
  options.steps = {1e-2, -1e-3};
  EXPECT_THROW(run_comparison(options), SceneError);
}

// Until an IDA integrator is built its runs fail with a message; once it is, they succeed. Either way
// the study records a row and goes on. Only the bookkeeping is tested, so the shoe is made quick: a
// spring 100 times stiffer brings it to rest 10 times sooner (before 1 s), in a window just long enough
// for the times of the literature checks.
TEST(Compare, IdaRunsAreRowsWhetherOrNotTheySucceed) {
  CompareOptions options = shoe_study();
  options.overrides = {"parameters.stiffness=2.4e6", "time.end=3.5"};
  options.integrators = {"ida", "ida-events"};
  options.steps.clear();
  options.tolerances = {1e-4};
  const Comparison comparison = run_comparison(options);
  ASSERT_EQ(comparison.rows.size(), 2u);
  bool all_ok = true;
  for (const CompareRow& row : comparison.rows) {
    EXPECT_EQ(row.parameter, "integrator.rtol");
    if (!row.ok) {
      EXPECT_FALSE(row.failure.empty());
    }
    all_ok = all_ok && row.ok;
  }
  EXPECT_EQ(comparison.rows[0].integrator, "ida");
  EXPECT_EQ(comparison.rows[1].integrator, "ida-events");
  EXPECT_EQ(comparison.all_ok(), all_ok);
}

}  // namespace
}  // namespace csim

namespace csim {
namespace {

// Without (or instead of) an analytical solution, a converged event-driven run is the reference: the
// Moreau–Jean deviation from it falls with the step, and the CSV says what the reference was.
TEST(Compare, ReferenceRunReplacesTheAnalyticalSolution) {
  CompareOptions options;
  options.scene_file = CSIM_SOURCE_DIR "/scenes/sdnv104-rigid/scene.yaml";
  options.integrators = {"moreau-jean"};
  options.steps = {1e-2, 1e-3};
  options.repeats = 1;
  options.reference = "ida-events";
  const Comparison comparison = run_comparison(options);
  EXPECT_TRUE(comparison.trajectory_reference);
  ASSERT_EQ(comparison.rows.size(), 2u);
  EXPECT_LT(comparison.rows[1].max_rel_error, 0.2 * comparison.rows[0].max_rel_error);
  EXPECT_GT(comparison.rows[1].max_rel_error, 0.0);
  EXPECT_NE(work_precision_csv(comparison).find("# reference: a converged ida-events run"), std::string::npos);
}

TEST(Compare, UnknownReferenceIsBadInput) {
  CompareOptions options;
  options.scene_file = CSIM_SOURCE_DIR "/scenes/sdnv104-rigid/scene.yaml";
  options.integrators = {"moreau-jean"};
  options.steps = {1e-2};
  options.reference = "exact";
  EXPECT_THROW(run_comparison(options), SceneError);
}

}  // namespace
}  // namespace csim
