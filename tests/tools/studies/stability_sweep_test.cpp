// The stability study on the stress block: runs are judged (outcome, worst error, energy invariants),
// bad sweeps files are rejected with located errors before any run, an IDA run that gives up becomes a
// `stopped` row rather than an exception, and the CI subset's Moreau–Jean rows keep the physical
// invariants: exact stick below the friction threshold, the exact slide above it, never energy created.
#include "tools/scene/scene_error.h"
#include "tools/studies/stability_sweep.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace csim {
namespace {

const std::string kScene = std::string(CSIM_SOURCE_DIR) + "/scenes/stress-block/scene.yaml";

class StabilitySweepTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = std::filesystem::temp_directory_path() / ("csim-stress-test-" + std::to_string(getpid()));
    std::filesystem::create_directories(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = (directory_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  StabilityOptions options(const std::string& sweeps_file) const {
    StabilityOptions o;
    o.scene_file = kScene;
    o.sweeps_file = sweeps_file;
    return o;
  }
  std::string error_of(const StabilityOptions& o) const {
    try {
      run_stability_sweep(o);
    } catch (const SceneError& e) {
      return e.what();
    }
    return "no SceneError";
  }

  std::filesystem::path directory_;
};

std::string read(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

const StabilityRow& row_of(const StabilityStudy& study, const std::string& case_name, const std::string& integrator) {
  const auto row = std::find_if(study.rows.begin(), study.rows.end(), [&](const StabilityRow& r) {
    return r.case_name() == case_name && r.integrator == integrator;
  });
  if (row == study.rows.end()) throw std::runtime_error("no row " + case_name + " " + integrator);
  return *row;
}

TEST_F(StabilitySweepTest, TwoMoreauJeanCasesPassWithTheirEnergyBalanced) {
  const std::string file = write("two.yaml",
                                 "integrators: [moreau-jean]\n"
                                 "sweeps:\n"
                                 "  threshold: {key: parameters.force_ratio, values: [0.5, 2]}\n");
  std::vector<std::string> reported;
  const StabilityStudy study = run_stability_sweep(options(file), [&](const StabilityRow& r) { reported.push_back(r.value); });
  EXPECT_EQ(study.scene_name, "stress-block");
  ASSERT_EQ(study.rows.size(), 2u);
  EXPECT_EQ(reported, (std::vector<std::string>{"0.5", "2"}));
  for (const StabilityRow& row : study.rows) {
    EXPECT_EQ(row.sweep, "threshold");
    EXPECT_EQ(row.key, "parameters.force_ratio");
    EXPECT_EQ(row.integrator, "moreau-jean");
    EXPECT_EQ(row.outcome, StabilityOutcome::passed) << row.note();
    EXPECT_EQ(row.energy_verdict(), "ok");
    EXPECT_TRUE(row.non_finite.empty());
    EXPECT_FALSE(row.violates_invariant());
    EXPECT_EQ(row.steps, 10000);  // 1 s at 1e-4 s
    EXPECT_GT(row.wall_time, 0.0);
  }
  EXPECT_TRUE(study.invariants_hold());

  write_stability_markdown(study, directory_.string());
  write_stability_csv(study, directory_.string());
  const std::string md = read(directory_ / "stability.md");
  EXPECT_NE(md.find("## threshold (`parameters.force_ratio`)"), std::string::npos) << md;
  EXPECT_NE(md.find("| parameters.force_ratio=0.5 | moreau-jean | passed |"), std::string::npos) << md;
  const std::string csv = read(directory_ / "stability.csv");
  EXPECT_NE(csv.find("\nsweep,key,value,integrator,outcome,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\nthreshold,parameters.force_ratio,2,moreau-jean,passed,"), std::string::npos) << csv;
}

TEST_F(StabilitySweepTest, MalformedSweepsFilesAreRejectedWithTheKeyAndLine) {
  const std::string unknown = write("unknown.yaml",
                                    "integrators: [moreau-jean]\n"
                                    "sweeps:\n"
                                    "  mass: {key: parameters.mass, values: [1], integratorz: [ida]}\n");
  EXPECT_NE(error_of(options(unknown)).find("unknown.yaml:3: sweeps.mass.integratorz: unknown key"), std::string::npos)
      << error_of(options(unknown));
  const std::string missing = write("missing.yaml",
                                    "integrators: [moreau-jean]\n"
                                    "sweeps:\n"
                                    "  mass: {values: [1, 2]}\n");
  EXPECT_NE(error_of(options(missing)).find("missing.yaml:3: sweeps.mass.key: missing required key"),
            std::string::npos)
      << error_of(options(missing));
  const std::string integrator = write("integrator.yaml", "integrators: [rk4]\nsweeps: {m: {key: parameters.mass, values: [1]}}\n");
  EXPECT_NE(error_of(options(integrator)).find("integrators[0]: unknown integrator 'rk4'"), std::string::npos);
  const std::string not_in_scene =
      write("key.yaml", "integrators: [moreau-jean]\nsweeps:\n  m: {key: parameters.nope, values: [1]}\n");
  EXPECT_NE(error_of(options(not_in_scene)).find("key.yaml:3: sweeps.m.key: 'parameters.nope' is not"),
            std::string::npos)
      << error_of(options(not_in_scene));
  const std::string baseline =
      write("baseline.yaml", "baseline: [parameters.nope=1]\nintegrators: [moreau-jean]\nsweeps:\n"
                             "  m: {key: parameters.mass, values: [1]}\n");
  EXPECT_NE(error_of(options(baseline)).find("baseline.yaml:1: baseline: the scene rejects it"), std::string::npos)
      << error_of(options(baseline));
  StabilityOptions only = options(write("ok.yaml", "integrators: [moreau-jean]\nsweeps: {m: {key: parameters.mass, values: [1]}}\n"));
  only.only = {"mu"};
  EXPECT_NE(error_of(only).find("--only: no sweep named 'mu' (sweeps: m)"), std::string::npos) << error_of(only);
}

TEST_F(StabilitySweepTest, AnIdaRunThatGivesUpIsAStoppedRow) {
  const std::string file = write("hopeless.yaml",
                                 "sweeps:\n"
                                 "  budget: {key: integrator.max_steps, values: [10], integrators: [ida]}\n");
  StabilityStudy study;
  ASSERT_NO_THROW(study = run_stability_sweep(options(file)));
  ASSERT_EQ(study.rows.size(), 1u);
  const StabilityRow& row = study.rows[0];
  EXPECT_EQ(row.outcome, StabilityOutcome::stopped);
  EXPECT_NE(row.message.find("max_steps"), std::string::npos) << row.message;
  EXPECT_EQ(row.energy_verdict(), "-");
  EXPECT_FALSE(row.violates_invariant());  // an acceptable outcome for IDA
  EXPECT_TRUE(study.invariants_hold());
}

TEST_F(StabilitySweepTest, AMoreauJeanRunThatCannotRunViolatesTheInvariants) {
  // A value the scene rejects is a row (bad input), and an invariant violation, not an exception.
  const std::string file = write("bad-value.yaml",
                                 "integrators: [moreau-jean]\n"
                                 "sweeps:\n"
                                 "  mass: {key: parameters.mass, values: [-1]}\n");
  const StabilityStudy study = run_stability_sweep(options(file));
  ASSERT_EQ(study.rows.size(), 1u);
  EXPECT_EQ(study.rows[0].outcome, StabilityOutcome::bad_input);
  EXPECT_FALSE(study.rows[0].message.empty());
  EXPECT_FALSE(study.invariants_hold());
}

// The CI subset: every Moreau–Jean row holds the invariants whatever its accuracy, and the physics
// at the friction threshold is exact.
TEST_F(StabilitySweepTest, CiSubsetKeepsMoreauJeanPhysical) {
  const StabilityStudy study = run_stability_sweep(options(std::string(CSIM_SOURCE_DIR) + "/scenes/stress-block/stress-ci.yaml"));
  EXPECT_TRUE(study.invariants_hold());
  for (const StabilityRow& row : study.rows) {
    EXPECT_TRUE(row.non_finite.empty()) << row.case_name();
    if (row.integrator != "moreau-jean") continue;
    EXPECT_NE(row.outcome, StabilityOutcome::stopped) << row.case_name() << ": " << row.message;
    EXPECT_EQ(row.energy_verdict(), "ok") << row.case_name();
    EXPECT_GE(row.contact_dissipation, 0.0) << row.case_name();
  }
  const StabilityRow& stick = row_of(study, "parameters.force_ratio=0.999", "moreau-jean");
  EXPECT_EQ(stick.outcome, StabilityOutcome::passed);
  EXPECT_EQ(stick.worst_check, "position_at_end");
  EXPECT_EQ(stick.worst_error, 0.0);           // stick is exact: not a picometre of motion
  EXPECT_EQ(stick.contact_dissipation, 0.0);   // and nothing dissipated
  const StabilityRow& slide = row_of(study, "parameters.force_ratio=1.001", "moreau-jean");
  EXPECT_EQ(slide.outcome, StabilityOutcome::passed);
  EXPECT_LT(slide.worst_error, 1e-6);
  EXPECT_GT(slide.contact_dissipation, 0.0);
  // ω h = 0.1 (k = 1e6 N/m, m = 1 kg, h = 1e-4 s) and ω h = 0.1 (k = 100, h = 1e-2): the same error,
  // since the θ-method's error depends on ω h alone.
  EXPECT_NEAR(row_of(study, "parameters.stiffness=1e6", "moreau-jean").worst_error,
              row_of(study, "time.step=1e-2", "moreau-jean").worst_error, 1e-9);
}

}  // namespace
}  // namespace csim
