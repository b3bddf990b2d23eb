// csim sweep's cases and table: lists go together, grids multiply (the first slowest), bad lists are
// refused with the option named; a run of the stress block gives one row per case, failed cases
// included, with its checks, and each case writes its own folder.
#include "tools/scene/scene_error.h"
#include "tools/studies/sweep.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

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

// Issue 53: a key that --set could not replace fails every case alike, so the study is refused before its
// first case (exit 2 from csim sweep), naming where the key was given; a value the scene rejects stays
// the row of its own case (above).
TEST(SweepStudy, AKeyNoCaseCouldSetIsRefusedBeforeTheFirstCase) {
  const std::filesystem::path directory =
      std::filesystem::temp_directory_path() / ("csim-sweep-keys-test-" + std::to_string(getpid()));
  auto refused = [&](SweepOptions options, const std::string& expected) {
    options.scene_file = kScene;
    options.overrides = {"time.end=0.01"};
    options.case_directory = directory.string();
    std::size_t rows = 0;
    try {
      run_sweep(options, [&](const SweepRow&) { ++rows; });
      ADD_FAILURE() << "accepted; expected " << expected;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
    EXPECT_EQ(rows, 0u) << expected;
    EXPECT_FALSE(std::filesystem::exists(directory / "case-0001")) << expected;
  };
  SweepOptions options;
  options.set_lists = {"parameters.mu=0.1,0.2", "parameters.nosuch=1,2"};
  refused(options, "scene.yaml: --set-list: 'parameters.nosuch' is not a single value of the scene");
  options = {};
  options.grids = {"parameters.mu=0.1", "nosuch.key=1,2"};
  refused(options, "--grid: 'nosuch.key' is not a single value");
  options.grids = {"gravity=1,2"};  // a list: --set replaces single values only
  refused(options, "--grid: 'gravity' is not a single value");
  options.grids = {"parameters=1"};  // a section
  refused(options, "--grid: 'parameters' is not a single value");
  // An integrator's own key, under an integrator that does not read it (moreau-jean has no rtol).
  options.grids = {"integrator.type=ida,moreau-jean", "integrator.rtol=1e-6"};
  refused(options, "--grid: 'integrator.rtol' is not a setting of the integrator moreau-jean");
  // A file of explicit cases: the file and the line of the setting.
  const std::string file = (std::filesystem::temp_directory_path() /
                            ("csim-sweep-keys-" + std::to_string(getpid()) + ".yaml")).string();
  {
    std::ofstream out(file);
    out << "cases:\n  - [parameters.mu=0.1]\n  - [parameters.mu=0.2, bodies.block.masss=2]\n";
  }
  options = {};
  options.sweeps_file = file;
  refused(options, ".yaml:3: cases: 'bodies.block.masss' is not a single value");
  std::filesystem::remove(file);
  std::filesystem::remove_all(directory);
}

TEST(SweepStudy, AKeyTheCaseIntegratorReadsIsAccepted) {
  SweepOptions options;
  options.scene_file = kScene;
  options.overrides = {"time.end=0.01"};
  options.set_lists = {"integrator.type=ida,ida", "integrator.rtol=1e-6,1e-8"};
  options.grids = {"contact_solver.tolerance=1e-10"};  // a key the file leaves to its default
  const SweepStudy study = run_sweep(options);
  ASSERT_EQ(study.rows.size(), 2u);
  for (const SweepRow& row : study.rows) EXPECT_NE(row.status, "bad input") << row.message;
}

}  // namespace
}  // namespace csim
