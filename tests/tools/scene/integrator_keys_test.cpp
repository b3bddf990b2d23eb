// The integrator keys the chosen integrator ignores (integrator_keys.h): refused when given for it,
// dropped when they belong to the file's own integrator and --set chose another.
#include "tools/scene/integrator_keys.h"
#include "tools/scene/scene.h"
#include "tests/tools/scene/scene_file_test.h"

#include <gtest/gtest.h>


namespace csim {
namespace {

std::string scene_with(const std::string& integrator_line) {
  return R"(dimension: 2
gravity: [0, -9.81]
bodies:
  block:
    type: rigid
    mass: 1
    position: [0, 0.5]
    shapes:
      cube: {type: box, size: [1, 1]}
  ground:
    type: fixed
    shapes:
      top: {type: halfspace, normal: [0, 1]}
contacts:
  block_on_ground: {between: [block, ground], mu: 0.3}
time: {end: 0.1, step: 0.01}
)" + integrator_line + "\n";
}

class IntegratorKeysTest : public SceneFileTest {
 protected:
  // The error of the block scene with this integrator line ("" if it loaded).
  std::string error_with(const std::string& integrator_line, const std::vector<std::string>& overrides = {}) {
    return error_of(write(scene_with(integrator_line)), overrides);
  }
};

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(IntegratorKeyTable, WhoReadsWhat) {
  EXPECT_TRUE(integrator_reads(Integrator::moreau_jean, "theta"));
  EXPECT_FALSE(integrator_reads(Integrator::ida, "theta"));
  EXPECT_TRUE(integrator_reads(Integrator::ida_events, "rtol"));
  EXPECT_FALSE(integrator_reads(Integrator::quasi_static, "rtol"));
  EXPECT_TRUE(integrator_reads(Integrator::quasi_static, "max_cutbacks"));
  EXPECT_FALSE(integrator_reads(Integrator::moreau_jean, "max_cutbacks"));
  EXPECT_TRUE(integrator_reads(Integrator::moreau_jean, "newton_tolerance"));  // finite-strain bodies
  EXPECT_FALSE(integrator_reads(Integrator::ida, "newton_tolerance"));
  for (Integrator integrator : kIntegrators) EXPECT_TRUE(integrator_reads(integrator, "type"));
  EXPECT_FALSE(is_integrator_key("type"));
  EXPECT_FALSE(is_integrator_key("thetta"));
}

TEST_F(IntegratorKeysTest, AKeyWrittenForTheDeclaredIntegratorThatIgnoresItIsRefused) {
  const std::string theta = error_with("integrator: {type: ida, theta: 0.5}");
  EXPECT_TRUE(contains(theta, "integrator.theta")) << theta;
  EXPECT_TRUE(contains(theta, "ida integrator")) << theta;
  EXPECT_TRUE(contains(theta, "moreau-jean does")) << theta;
  EXPECT_TRUE(contains(theta, "remove it from the scene")) << theta;
  const std::string rtol = error_with("integrator: {type: quasi-static, rtol: 1e-8}");
  EXPECT_TRUE(contains(rtol, "integrator.rtol")) << rtol;
  EXPECT_TRUE(contains(rtol, "quasi-static")) << rtol;
  // No type written: the file's integrator is the default, moreau-jean.
  const std::string cutbacks = error_with("integrator: {max_cutbacks: 2}");
  EXPECT_TRUE(contains(cutbacks, "integrator.max_cutbacks")) << cutbacks;
  EXPECT_TRUE(contains(cutbacks, "moreau-jean integrator")) << cutbacks;
}

TEST_F(IntegratorKeysTest, AKeySetForAnIntegratorThatIgnoresItIsRefused) {
  const std::string message = error_with("", {"integrator.max_cutbacks=3"});
  EXPECT_TRUE(contains(message, "integrator.max_cutbacks")) << message;
  EXPECT_TRUE(contains(message, "drop --set integrator.max_cutbacks")) << message;
  const std::string switched = error_with("integrator: {type: moreau-jean}", {"integrator.type=ida", "integrator.theta=1"});
  EXPECT_TRUE(contains(switched, "integrator.theta")) << switched;
  EXPECT_TRUE(contains(switched, "ida integrator")) << switched;
}

TEST_F(IntegratorKeysTest, TheFilesOwnKeysAreDroppedWhenSetChoosesAnotherIntegrator) {
  const auto scene = load_scene(write(scene_with("integrator: {type: moreau-jean, theta: 0.6, close_gaps: false}")),
                                {"integrator.type=ida", "integrator.rtol=1e-8"});
  EXPECT_EQ(scene->run.integrator, Integrator::ida);
  EXPECT_EQ(scene->run.ida.rtol, 1e-8);
  const std::string dump = dump_config(*scene);
  EXPECT_FALSE(contains(dump, "theta")) << dump;
  EXPECT_FALSE(contains(dump, "close_gaps")) << dump;
  EXPECT_TRUE(contains(dump, "rtol")) << dump;
  // The effective configuration loads again as it is.
  const auto again = load_scene(write(dump), {});
  EXPECT_EQ(again->run.integrator, Integrator::ida);
  EXPECT_EQ(again->run.ida.rtol, 1e-8);
}

TEST_F(IntegratorKeysTest, SetTypeWhereTheFileHasNoneReachesTheOtherIntegratorsKeys) {
  const auto scene = load_scene(write(scene_with("")), {"integrator.type=ida-events", "integrator.atol=1e-10"});
  EXPECT_EQ(scene->run.integrator, Integrator::ida_events);
  EXPECT_EQ(scene->run.ida.atol, 1e-10);
}

TEST_F(IntegratorKeysTest, AFileKeyNoIntegratorOfTheFileReadsIsRefusedEvenWhenSwitched) {
  // rtol is not moreau-jean's: the file is wrong on its own, whatever --set chooses.
  const std::string message = error_with("integrator: {type: moreau-jean, rtol: 1e-8}", {"integrator.type=quasi-static"});
  EXPECT_TRUE(contains(message, "integrator.rtol")) << message;
}

TEST_F(IntegratorKeysTest, DumpOfEachIntegratorHoldsOnlyItsKeysAndReloads) {
  for (Integrator integrator : {Integrator::moreau_jean, Integrator::ida, Integrator::ida_events}) {
    const auto scene = load_scene(write(scene_with("")), {"integrator.type=" + integrator_name(integrator)});
    const std::string dump = dump_config(*scene);
    EXPECT_EQ(contains(dump, "theta"), integrator == Integrator::moreau_jean) << dump;
    EXPECT_EQ(contains(dump, "rtol"), is_ida(integrator)) << dump;
    EXPECT_EQ(load_scene(write(dump), {})->run.integrator, integrator);
  }
}

// A --set on a key left to its default reads the scene twice, the first reading writing every default
// into the tree: the contact solver's omega must come out of it as `auto` (the relaxed attempt), not
// as a given number (which would switch the attempt off and change a pile's solves).
TEST_F(IntegratorKeysTest, ASetOnADefaultKeyLeavesTheRelaxedAttemptOn) {
  const auto plain = load_scene(write(scene_with("")), {});
  const auto set = load_scene(write(scene_with("")), {"integrator.close_gaps=true"});
  EXPECT_TRUE(plain->run.contact_solver.relax_sparse);
  EXPECT_TRUE(set->run.contact_solver.relax_sparse);
  const auto given = load_scene(write(scene_with("")), {"contact_solver.omega=1.0"});
  EXPECT_FALSE(given->run.contact_solver.relax_sparse);
  EXPECT_EQ(given->run.contact_solver.omega, 1.0);
  EXPECT_TRUE(load_scene(write(dump_config(*set)), {})->run.contact_solver.relax_sparse);
  const std::string bad = error_of(write(scene_with("contact_solver: {omega: fast}")));
  EXPECT_TRUE(contains(bad, "contact_solver.omega")) << bad;
}

TEST_F(IntegratorKeysTest, SleepingIsMoreauJeansAndOffByDefault) {
  EXPECT_FALSE(load_scene(write(scene_with("")), {})->run.moreau_jean.sleep.enabled());
  const auto scene = load_scene(write(scene_with("integrator: {sleep_speed: 1e-3, sleep_time: 0.2}")), {});
  EXPECT_EQ(scene->run.moreau_jean.sleep.speed, 1e-3);
  EXPECT_EQ(scene->run.moreau_jean.sleep.time, 0.2);
  const std::string message = error_with("integrator: {type: generalized-alpha, sleep_speed: 1e-3}");
  EXPECT_TRUE(contains(message, "integrator.sleep_speed")) << message;
}

}  // namespace
}  // namespace csim
