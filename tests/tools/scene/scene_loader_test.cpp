// Scene-loader errors: each bad input gives a SceneError whose message names the file, the key path
// and (where the key is in the file) its line.
#include "tools/scene/scene.h"
#include "engine/bodies/fe_body.h"
#include "tests/tools/scene/scene_file_test.h"

#include <gtest/gtest.h>

#include <cmath>

namespace csim {
namespace {

const char* kValidScene = R"(dimension: 2
parameters:
  mass: 2
  mu: 0.3
gravity: [0, -9.81]
bodies:
  block:
    type: rigid
    mass: =mass
    position: [0, 0.5]
    shapes:
      cube: {type: box, size: [1, 1]}
  ground:
    type: fixed
    shapes:
      top: {type: halfspace, normal: [0, 1]}
contacts:
  block_on_ground: {between: [block, ground], mu: =mu}
time: {end: 0.1, step: 0.01}
probes:
  x: {displacement: {body: block, component: x}}
checks:
  still: {probe: x, final: true, reference: 0, tolerance: {absolute: 1e-12}, kind: analytical, source: test}
)";

class SceneLoaderTest : public SceneFileTest {
 protected:
  // Replaces the first occurrence of `from` in the valid scene.
  std::string variant(const std::string& from, const std::string& to) {
    std::string text = kValidScene;
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return write(text.replace(at, from.size(), to));
  }
};

TEST_F(SceneLoaderTest, ValidSceneLoads) {
  const auto scene = load_scene(write(kValidScene), {});
  EXPECT_EQ(scene->world.bodies.size(), 2u);
  EXPECT_EQ(scene->world.velocity_size, 3);
  EXPECT_DOUBLE_EQ(scene->world.contact_laws[0].mu(0), 0.3);
  EXPECT_DOUBLE_EQ(scene->world.bodies[0].body->mass(), 2.0);
}

TEST_F(SceneLoaderTest, MalformedYamlNamesFileAndLine) {
  const std::string file = variant("time: {end: 0.1, step: 0.01}", "time: {end: 0.1, step: [0.01}");
  const std::string message = error_of(file);
  EXPECT_NE(message.find(file), std::string::npos) << message;
  EXPECT_NE(message.find("malformed YAML"), std::string::npos) << message;
  EXPECT_NE(message.find(":19"), std::string::npos) << message;
}

TEST_F(SceneLoaderTest, UnknownKeyNamesPathAndLine) {
  const std::string message = error_of(variant("    mass: =mass\n", "    mass: =mass\n    mas: 3\n"));
  EXPECT_NE(message.find("bodies.block.mas"), std::string::npos) << message;
  EXPECT_NE(message.find("unknown key"), std::string::npos) << message;
  EXPECT_NE(message.find(":10:"), std::string::npos) << message;
}

TEST_F(SceneLoaderTest, UnknownTopLevelKey) {
  const std::string message = error_of(variant("dimension: 2\n", "dimension: 2\nintegrater: {type: ida}\n"));
  EXPECT_NE(message.find("integrater"), std::string::npos) << message;
}

TEST_F(SceneLoaderTest, WrongTypeNamesKey) {
  const std::string message = error_of(variant("mass: =mass", "mass: heavy"));
  EXPECT_NE(message.find("bodies.block.mass"), std::string::npos) << message;
  EXPECT_NE(message.find("expected a number"), std::string::npos) << message;
}

TEST_F(SceneLoaderTest, NegativeAndZeroMass) {
  for (const char* value : {"-1", "0"}) {
    const std::string message = error_of(variant("mass: =mass", std::string("mass: ") + value));
    EXPECT_NE(message.find("bodies.block.mass"), std::string::npos) << message;
    EXPECT_NE(message.find("must be > 0"), std::string::npos) << message;
  }
}

TEST_F(SceneLoaderTest, NegativeFrictionCoefficient) {
  const std::string message = error_of(variant("  mu: 0.3", "  mu: -0.3"));
  EXPECT_NE(message.find("contacts.block_on_ground.mu"), std::string::npos) << message;
  EXPECT_NE(message.find(">= 0"), std::string::npos) << message;
}

TEST_F(SceneLoaderTest, ElasticSlipIsNonNegativeAndForTheQuasiStaticStepperOnly) {
  std::string message = error_of(variant("mu: =mu}", "mu: =mu, elastic_slip: -0.01}"));
  EXPECT_NE(message.find("contacts.block_on_ground.elastic_slip"), std::string::npos) << message;
  EXPECT_NE(message.find(">= 0"), std::string::npos) << message;
  // The valid scene runs Moreau–Jean, which keeps no penalty-friction history.
  message = error_of(variant("mu: =mu}", "mu: =mu, elastic_slip: 0.01}"));
  EXPECT_NE(message.find(".yaml:18: contacts.block_on_ground.elastic_slip"), std::string::npos) << message;
  EXPECT_NE(message.find("quasi-static stepper only"), std::string::npos) << message;
  EXPECT_EQ(error_of(variant("mu: =mu}", "mu: =mu, elastic_slip: 0}")), "");
}

TEST_F(SceneLoaderTest, NonPositiveStep) {
  for (const char* step : {"0", "-0.01"}) {
    const std::string message = error_of(variant("step: 0.01", std::string("step: ") + step));
    EXPECT_NE(message.find("time.step"), std::string::npos) << message;
    EXPECT_NE(message.find("must be > 0"), std::string::npos) << message;
  }
}

TEST_F(SceneLoaderTest, MissingFile) {
  const std::string message = error_of("/nonexistent/scene.yaml");
  EXPECT_NE(message.find("/nonexistent/scene.yaml"), std::string::npos) << message;
  EXPECT_NE(message.find("cannot open"), std::string::npos) << message;
}

TEST_F(SceneLoaderTest, OverrideOfMissingKey) {
  const std::string message = error_of(write(kValidScene), {"parameters.muu=0.5"});
  EXPECT_NE(message.find("parameters.muu"), std::string::npos) << message;
  EXPECT_NE(message.find("not in the scene"), std::string::npos) << message;
}

TEST_F(SceneLoaderTest, OverrideChangesEveryUseOfAParameter) {
  const auto scene = load_scene(write(kValidScene), {"parameters.mu=0.7", "parameters.mass=5"});
  EXPECT_DOUBLE_EQ(scene->world.contact_laws[0].mu(0), 0.7);
  EXPECT_DOUBLE_EQ(scene->world.contact_laws[0].mu(1), 0.7);
  EXPECT_DOUBLE_EQ(scene->world.bodies[0].body->mass(), 5.0);
}

// A parameter's kind (number or text) follows from its spelling; an override may not change it.
TEST_F(SceneLoaderTest, OverrideKeepsTheKindOfAParameter) {
  const std::string file = variant("  mu: 0.3\n", "  mu: 0.3\n  law: neo-hookean\n");
  std::string message = error_of(file, {"parameters.mu=abc"});
  EXPECT_NE(message.find(".yaml:4: parameters.mu: --set parameters.mu=abc: mu is a numeric parameter"),
            std::string::npos) << message;
  EXPECT_NE(message.find("expected a number or an '=expression'"), std::string::npos) << message;
  message = error_of(file, {"parameters.law=3"});
  EXPECT_NE(message.find(".yaml:5: parameters.law: --set parameters.law=3: law is a text parameter"),
            std::string::npos) << message;
  EXPECT_EQ(error_of(file, {"parameters.mu==0.1*4", "parameters.law=saint-venant-kirchhoff"}), "");
  EXPECT_DOUBLE_EQ(load_scene(file, {"parameters.mu==0.1*4"})->world.contact_laws[0].mu(0), 0.4);
}

TEST_F(SceneLoaderTest, CloseGapsIsOnByDefaultAndReadAsABoolean) {
  EXPECT_TRUE(load_scene(write(kValidScene), {})->run.moreau_jean.close_gaps);
  EXPECT_FALSE(load_scene(write(kValidScene), {"integrator.close_gaps=false"})->run.moreau_jean.close_gaps);
  const std::string message = error_of(write(kValidScene), {"integrator.close_gaps=sometimes"});
  EXPECT_NE(message.find("integrator.close_gaps"), std::string::npos) << message;
}

TEST_F(SceneLoaderTest, UnknownNameInExpression) {
  const std::string message = error_of(variant("mass: =mass", "mass: =mas*2"));
  EXPECT_NE(message.find("bodies.block.mass"), std::string::npos) << message;
  EXPECT_NE(message.find("mas"), std::string::npos) << message;
}

TEST_F(SceneLoaderTest, UnknownBodyInContact) {
  const std::string message = error_of(variant("between: [block, ground]", "between: [block, floor]"));
  EXPECT_NE(message.find("contacts.block_on_ground.between"), std::string::npos) << message;
  EXPECT_NE(message.find("floor"), std::string::npos) << message;
}

TEST_F(SceneLoaderTest, CheckWithUnknownProbe) {
  const std::string message = error_of(variant("{probe: x,", "{probe: y,"));
  EXPECT_NE(message.find("checks.still.probe"), std::string::npos) << message;
}

TEST_F(SceneLoaderTest, DumpConfigContainsDefaults) {
  const auto scene = load_scene(write(kValidScene), {});
  const std::string text = dump_config(*scene);
  EXPECT_NE(text.find("theta: 0.5"), std::string::npos) << text;
  EXPECT_NE(text.find("tolerance: 1e-12"), std::string::npos) << text;
  // The dump is itself a valid scene that loads to the same world.
  const auto again = load_scene(write(text), {});
  EXPECT_EQ(again->world.bodies.size(), scene->world.bodies.size());
}

// A ring one element wide (hexa8 annulus), held in z everywhere: plane strain in a 3D scene.
const char* kRingScene = R"(dimension: 3
bodies:
  ring:
    type: elastic
    mesh: {generator: annulus, inner_radius: 1, outer_radius: 2, width: 0.5, divisions: [16, 2, 1],
           element: hexa8, position: [0, 0, 0.25]}
    material: {young: 800, poisson: 0.3, density: 1}
    fixed: {all: [z]}
time: {end: 0.1, step: 0.01}
)";

TEST_F(SceneLoaderTest, Hexa8AnnulusLoadsWithItsWidthAndThirdDivision) {
  const auto scene = load_scene(write(kRingScene), {});
  ASSERT_EQ(scene->world.bodies.size(), 1u);
  EXPECT_EQ(scene->world.bodies[0].body->velocity_size(), 2 * 16 * 3 * 2);  // x, y free at every node
}

TEST_F(SceneLoaderTest, AnnulusWidthOnlyForHexa8) {
  auto ring = [&](const std::string& from, const std::string& to) {
    std::string text = kRingScene;
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return write(text.replace(at, from.size(), to));
  };
  const std::string plane = error_of(ring("divisions: [16, 2, 1],\n           element: hexa8, position: [0, 0, 0.25]",
                                          "divisions: [16, 2], element: quad4"));
  EXPECT_NE(plane.find("bodies.ring.mesh.width: only for a hexa8 annulus"), std::string::npos) << plane;
  const std::string missing = error_of(ring("width: 0.5, ", ""));
  EXPECT_NE(missing.find("bodies.ring.mesh"), std::string::npos) << missing;
  EXPECT_NE(missing.find("width"), std::string::npos) << missing;
  const std::string negative = error_of(ring("width: 0.5", "width: -0.5"));
  EXPECT_NE(negative.find("bodies.ring.mesh.width: must be > 0"), std::string::npos) << negative;
  const std::string two = error_of(ring("[16, 2, 1]", "[16, 2]"));
  EXPECT_NE(two.find("bodies.ring.mesh.divisions: expected a list of 3 numbers"), std::string::npos) << two;
}

}  // namespace
}  // namespace csim

namespace csim {
namespace {

// A --set on a key the file leaves to its default reads the scene twice (the first reading fills the
// defaults in). The first reading must not rewrite the tree: a prescribed {value, until} map once
// became its value table, and the hub of the rolling ring was never released.
TEST(SceneLoaderOverrides, OverrideOnADefaultKeepsPrescribedUntil) {
  const std::string ring = CSIM_SOURCE_DIR "/scenes/rolling-ring/scene.yaml";
  const auto plain = load_scene(ring, {});
  const auto overridden = load_scene(ring, {"materials.mooney-rivlin.formulation=mean-dilatation"});
  ASSERT_EQ(plain->world.prescribed.size(), overridden->world.prescribed.size());
  bool released = false;
  for (std::size_t i = 0; i < plain->world.prescribed.size(); ++i) {
    EXPECT_EQ(plain->world.prescribed[i].until, overridden->world.prescribed[i].until) << i;
    released = released || std::isfinite(overridden->world.prescribed[i].until);
  }
  EXPECT_TRUE(released);  // the hub's spin is held during the press only
  EXPECT_EQ(dump_config(*plain), dump_config(*overridden));
}

// Every entry of the materials map is checked, also those the parameters do not pick (the rolling ring
// uses mooney-rivlin unless told; its linear-elastic entry was read only when picked).
TEST(SceneLoaderMaterials, EveryEntryIsCheckedUsedOrNot) {
  const std::string ring = CSIM_SOURCE_DIR "/scenes/rolling-ring/scene.yaml";
  auto error_of = [&](const std::vector<std::string>& overrides) {
    try {
      load_scene(ring, overrides);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error_of({"materials.linear-elastic.young=-1"})
                .find("scene.yaml:48: materials.linear-elastic: material: young = -1"),
            std::string::npos);
  EXPECT_NE(error_of({"parameters.elastic_law=hooke"})
                .find("materials.linear-elastic.law: unknown material law 'hooke'"),
            std::string::npos);
  EXPECT_NE(error_of({"parameters.material=linear-elastic", "materials.mooney-rivlin.bulk=0"})
                .find("materials.mooney-rivlin"),
            std::string::npos);
}

// Mooney–Rivlin rings take their element's mixed formulation unless told: Q2/P1 on quad8, Q1/P0 on
// quad4; a linear pressure on quad4 (which locks) is refused with the key and its line.
TEST(SceneLoaderFormulation, MooneyRivlinDefaultsToTheElementsMixedPair) {
  const std::string ring = CSIM_SOURCE_DIR "/scenes/rolling-ring/scene.yaml";
  auto formulation_of = [](const Scene& scene) {
    const auto& ring_body = *scene.world.bodies[scene.world.body_index("ring")].body->finite_elements();
    return ring_body.finite_strain_law()->formulation;
  };
  EXPECT_EQ(formulation_of(*load_scene(ring, {})), FiniteStrainFormulation::mean_dilatation);
  EXPECT_EQ(formulation_of(*load_scene(ring, {"parameters.element=quad8", "parameters.divisions_circumferential=18",
                                              "parameters.divisions_radial=3"})),
            FiniteStrainFormulation::linear_dilatation);
  EXPECT_EQ(formulation_of(*load_scene(ring, {"parameters.element=quad8", "materials.mooney-rivlin.formulation=mean-dilatation"})),
            FiniteStrainFormulation::mean_dilatation);
  try {
    load_scene(ring, {"materials.mooney-rivlin.formulation=linear-dilatation"});
    ADD_FAILURE() << "linear-dilatation on quad4 loaded";
  } catch (const SceneError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("scene.yaml"), std::string::npos) << message;
    EXPECT_NE(message.find("formulation"), std::string::npos) << message;
    EXPECT_NE(message.find("needs quad8 elements, not quad4"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace csim
