// csim sweep's cases and table: lists go together, grids multiply (the first slowest), bad lists are
// refused with the option named; a run of the stress block gives one row per case, failed cases
// included, with its checks, and each case writes its own folder.
#include "tools/scene/scene_error.h"
#include "tools/studies/sweep.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

namespace csim {
namespace {

const std::string kScene = std::string(CSIM_SOURCE_DIR) + "/scenes/stress-block/scene.yaml";

std::vector<std::vector<std::string>> settings(const SweepOptions& options) {
  std::vector<std::vector<std::string>> out;
  for (const SweepCase& c : sweep_cases(options)) out.push_back(c.settings);
  return out;
}

TEST(SweepCases, ListsGoTogetherAndGridsMultiplyFirstSlowest) {
  SweepOptions options;
  options.scene_file = kScene;
  options.set_lists = {"parameters.mu=0,1", "parameters.mass=2,3"};
  options.grids = {"time.step=1e-3,1e-4", "integrator.type=moreau-jean,ida"};
  const auto cases = settings(options);
  ASSERT_EQ(cases.size(), 8u);
  EXPECT_EQ(cases[0], (std::vector<std::string>{"parameters.mu=0", "parameters.mass=2", "time.step=1e-3",
                                                "integrator.type=moreau-jean"}));
  EXPECT_EQ(cases[1].back(), "integrator.type=ida");
  EXPECT_EQ(cases[2][2], "time.step=1e-4");
  EXPECT_EQ(cases[4][0], "parameters.mu=1");
  EXPECT_EQ(cases[4][1], "parameters.mass=3");
}

TEST(SweepCases, BadListsAreRefusedNamingTheOption) {
  auto refused = [](SweepOptions options, const std::string& expected) {
    options.scene_file = kScene;
    try {
      sweep_cases(options);
      ADD_FAILURE() << "accepted; expected " << expected;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  SweepOptions options;
  refused(options, "no cases");
  options.grids = {"parameters.mu"};
  refused(options, "--grid: expected KEY=V1,V2");
  options.grids = {"parameters.mu=1,,2"};
  refused(options, "an empty value");
  options.grids = {"parameters.mu=1", "parameters.mu=2"};
  refused(options, "'parameters.mu' is given twice");
  options.grids = {};
  options.set_lists = {"parameters.mu=0,1", "parameters.mass=1"};
  refused(options, "different lengths");
  options.sweeps_file = std::string(CSIM_SOURCE_DIR) + "/scenes/stress-block/stress-ci.yaml";
  refused(options, "not both");
}

TEST(SweepStudy, OneRowPerCaseWithItsChecksFailuresIncluded) {
  const std::filesystem::path directory =
      std::filesystem::temp_directory_path() / ("csim-sweep-test-" + std::to_string(getpid()));
  SweepOptions options;
  options.scene_file = kScene;
  options.overrides = {"time.end=0.2"};
  options.grids = {"parameters.mu=0.3,-1", "integrator.type=moreau-jean,ida"};
  options.case_directory = directory.string();
  const SweepStudy study = run_sweep(options);
  ASSERT_EQ(study.rows.size(), 4u);
  EXPECT_EQ(study.rows[0].settings, (std::vector<std::string>{"parameters.mu=0.3", "integrator.type=moreau-jean"}));
  EXPECT_GT(study.rows[0].steps, 0);
  EXPECT_GT(study.rows[0].contact_solves, 0);
  EXPECT_FALSE(study.rows[0].checks.empty());
  for (std::size_t k : {2u, 3u}) {  // a negative friction coefficient: bad input, a row all the same
    EXPECT_EQ(study.rows[k].exit_status, 2) << k;
    EXPECT_EQ(study.rows[k].status, "bad input") << k;
    EXPECT_NE(study.rows[k].message.find("mu"), std::string::npos) << study.rows[k].message;
  }
  EXPECT_TRUE(std::filesystem::exists(directory / "case-0001" / "summary.json"));
  EXPECT_TRUE(std::filesystem::exists(directory / "case-0002" / "probes.csv"));
  EXPECT_FALSE(std::filesystem::exists(directory / "case-0003"));
  const std::string csv = sweep_csv(study);
  EXPECT_NE(csv.find("case,parameters.mu,integrator.type,exit_status,status,message,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n3,-1,moreau-jean,2,bad input,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("# placement: serial (1 process)"), std::string::npos);
  std::filesystem::remove_all(directory);
}

}  // namespace
}  // namespace csim
