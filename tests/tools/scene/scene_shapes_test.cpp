// Capsule, cylinder and convex shapes in scene files (docs/contract.md, Shapes): their keys, the
// default inertia from their closed forms, and the refusals (a plane scene, a hull without volume,
// a turned shape without inertia, an elastic body against them) with the file, line and key.
#include "engine/bodies/body.h"
#include "tests/tools/scene/scene_file_test.h"
#include "tools/scene/mesh_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace csim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Line 3: floor; line 4: the body under test, of mass 2 kg.
std::string scene(const std::string& shape, const std::string& body_extra = "", int dimension = 3) {
  return "dimension: " + std::to_string(dimension) + "\n"
         "bodies:\n"
         "  floor: {type: fixed, shapes: {surface: {type: halfspace, normal: " +
         (dimension == 3 ? "[0, 0, 1]" : "[0, 1]") + "}}}\n"
         "  thing: {type: rigid, mass: 2" + body_extra + ", shapes: {body: " + shape + "}}\n"
         "contacts:\n"
         "  ground: {between: [thing, floor], mu: 0.5}\n"
         "time: {end: 0.01, step: 1e-3}\n";
}

// The principal inertia (kg·m²) the loader gave the body: the rotational diagonal of its mass matrix.
Eigen::Vector3d inertia_of(const World& world) {
  const Body& body = *world.bodies[world.body_index("thing")].body;
  Triplets triplets;
  body.add_mass(0, triplets);
  Eigen::SparseMatrix<double> M(6, 6);
  M.setFromTriplets(triplets.begin(), triplets.end());
  return Eigen::MatrixXd(M).diagonal().tail<3>();
}

class SceneShapes : public SceneFileTest {};

TEST_F(SceneShapes, CylinderInertiaIsTheSolidCylinders) {
  const auto loaded = load_scene(write(scene("{type: cylinder, radius: 0.1, length: 0.4}")), {});
  const double across = 2.0 * (3 * 0.01 + 0.16) / 12.0;  // m (3 r² + L²) / 12
  const Eigen::Vector3d I = inertia_of(loaded->world);
  EXPECT_NEAR(I.x(), across, 1e-15);
  EXPECT_NEAR(I.y(), across, 1e-15);
  EXPECT_NEAR(I.z(), 2.0 * 0.01 / 2.0, 1e-15);  // m r² / 2
}

TEST_F(SceneShapes, CapsuleInertiaOfLengthZeroIsTheSpheres) {
  // A capsule of length 0 is a sphere (2/5 m r²); of radius r and length L, along its axis the sum of
  // its cylinder's m_c r²/2 and its ball's 2/5 m_s r², masses in proportion to volume.
  const Eigen::Vector3d ball = inertia_of(load_scene(write(scene("{type: capsule, radius: 0.1, length: 0}")), {})->world);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(ball(i), 0.4 * 2.0 * 0.01, 1e-15);
  const Eigen::Vector3d I = inertia_of(load_scene(write(scene("{type: capsule, radius: 0.1, length: 0.4}")), {})->world);
  const double cylinder_volume = kPi * 0.01 * 0.4, ball_volume = 4.0 / 3.0 * kPi * 1e-3;
  const double m_c = 2.0 * cylinder_volume / (cylinder_volume + ball_volume), m_s = 2.0 - m_c;
  EXPECT_NEAR(I.z(), 0.5 * m_c * 0.01 + 0.4 * m_s * 0.01, 1e-15);
  // Across: the cylinder's m_c (L²/12 + r²/4); each hemisphere (mass m_s/2) 83/320 m r² about its own
  // centroid, 3r/8 from its flat face, that face L/2 from the centre (parallel axes).
  const double hemisphere = 83.0 / 320.0 * 0.5 * m_s * 0.01 + 0.5 * m_s * std::pow(0.2 + 3.0 * 0.1 / 8.0, 2);
  EXPECT_NEAR(I.x(), m_c * (0.16 / 12.0 + 0.01 / 4.0) + 2.0 * hemisphere, 1e-15);
  EXPECT_NEAR(I.y(), I.x(), 1e-15);
}

TEST_F(SceneShapes, ConvexCubeInertiaIsTheBoxs) {
  const auto loaded = load_scene(write(scene(
      "{type: convex, vertices: [[-0.5, -0.4, -0.3], [0.5, -0.4, -0.3], [-0.5, 0.4, -0.3], [0.5, 0.4, -0.3],"
      " [-0.5, -0.4, 0.3], [0.5, -0.4, 0.3], [-0.5, 0.4, 0.3], [0.5, 0.4, 0.3], [0.1, 0.1, 0.1]]}")), {});
  const Eigen::Vector3d I = inertia_of(loaded->world);
  EXPECT_NEAR(I.x(), 2.0 * (0.64 + 0.36) / 12.0, 1e-14);
  EXPECT_NEAR(I.y(), 2.0 * (1.0 + 0.36) / 12.0, 1e-14);
  EXPECT_NEAR(I.z(), 2.0 * (1.0 + 0.64) / 12.0, 1e-14);
}

TEST_F(SceneShapes, PlaneScenesRefuseThemAtTheirType) {
  for (const std::string& shape : {std::string("{type: capsule, radius: 0.1, length: 0.4}"),
                                   std::string("{type: cylinder, radius: 0.1, length: 0.4}")}) {
    const std::string message = error_of(write(scene(shape, ", inertia: 1", 2)));
    EXPECT_NE(message.find(".yaml:4: bodies.thing.shapes.body.type: a "), std::string::npos) << message;
    EXPECT_NE(message.find("is a 3D shape"), std::string::npos) << message;
  }
}

TEST_F(SceneShapes, BadSizesAndFlatHullsAreRefusedAtTheirKey) {
  EXPECT_NE(error_of(write(scene("{type: capsule, radius: 0.1, length: -1}"))).find("shapes.body.length: must be >= 0"),
            std::string::npos);
  EXPECT_NE(error_of(write(scene("{type: cylinder, radius: 0, length: 1}"))).find("shapes.body.radius"),
            std::string::npos);
  const std::string flat = error_of(write(scene("{type: convex, vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]}")));
  EXPECT_NE(flat.find(".yaml:4: bodies.thing.shapes.body.vertices: a convex hull's points lie on one plane"),
            std::string::npos) << flat;
  const std::string few = error_of(write(scene("{type: convex, vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}")));
  EXPECT_NE(few.find("at least 4 points (3 given)"), std::string::npos) << few;
}

TEST_F(SceneShapes, ATurnedShapeOrAnOffCentreHullNeedsItsInertia) {
  const std::string turned = error_of(write(scene("{type: cylinder, radius: 0.1, length: 0.4, angle: 30}")));
  EXPECT_NE(turned.find("bodies.thing.inertia: required: the body's only shape is turned"), std::string::npos) << turned;
  EXPECT_EQ(error_of(write(scene("{type: cylinder, radius: 0.1, length: 0.4, angle: 30}", ", inertia: [1, 1, 1]"))), "");
  const std::string off_centre = error_of(write(scene("{type: convex, vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]}")));
  EXPECT_NE(off_centre.find("bodies.thing.inertia: required: the convex hull's centroid"), std::string::npos) << off_centre;
}

TEST_F(SceneShapes, AnElasticBodyAgainstACapsuleIsRefusedAtTheLaw) {
  const std::string text =
      "dimension: 3\n"
      "bodies:\n"
      "  block:\n"
      "    type: elastic\n"
      "    mesh: {generator: box, size: [1, 1, 0.25], divisions: [1, 1, 1], element: hexa8}\n"
      "    material: {young: 2.1e11, poisson: 0.3, density: 7800}\n"
      "    fixed: {zmin: [x, y, z]}\n"
      "  thing: {type: rigid, mass: 2, position: [0.5, 0.5, 0.4], shapes: {body: {type: capsule, radius: 0.1, length: 0.2}}}\n"
      "contacts:\n"
      "  touch: {between: [block, thing], mu: 0.5}\n"
      "time: {end: 0.01, step: 1e-3}\n";
  const std::string message = error_of(write(text));
  EXPECT_NE(message.find(".yaml:10: contacts.touch.between: elastic body 'block' against body 'thing'"),
            std::string::npos) << message;
}

// A file beside the test's scene files, removed at the end of the test.
class MeshFiles : public SceneFileTest {
 protected:
  std::string file(const std::string& name, const std::string& bytes) {
    const auto path = std::filesystem::temp_directory_path() / ("csim_mesh_" + name);
    std::ofstream(path, std::ios::binary) << bytes;
    paths_.push_back(path);
    return path.string();
  }
  void TearDown() override {
    for (const auto& p : paths_) std::filesystem::remove(p);
    SceneFileTest::TearDown();
  }

 private:
  std::vector<std::filesystem::path> paths_;
};

TEST_F(MeshFiles, ObjQuadsSplitIntoFansWithSlashedAndNegativeIndices) {
  const TriangleMesh mesh = read_mesh_file(file("quad.obj",
      "# a unit square and a triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n"
      "f 1/1/1 2/2/1 3/3/1 4/4/1\nf -4 -3 -1\n"));
  ASSERT_EQ(mesh.vertices.size(), 4u);
  ASSERT_EQ(mesh.triangles.size(), 3u);
  EXPECT_EQ(mesh.triangles[0], (std::array<int, 3>{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[1], (std::array<int, 3>{0, 2, 3}));
  EXPECT_EQ(mesh.triangles[2], (std::array<int, 3>{0, 1, 3}));
}

TEST_F(MeshFiles, StlAsciiAndBinaryGiveTheSameMergedMesh) {
  const TriangleMesh ascii = read_mesh_file(file("two.stl",
      "solid two\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 1 1 0\n"
      "  endloop\n endfacet\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 1 0\n"
      "   vertex 0 1 0\n  endloop\n endfacet\nendsolid two\n"));
  std::string bytes(84 + 2 * 50, '\0');
  const std::uint32_t count = 2;
  std::memcpy(&bytes[80], &count, 4);
  const float corners[2][9] = {{0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 0, 1, 1, 0, 0, 1, 0}};
  for (int t = 0; t < 2; ++t) std::memcpy(&bytes[84 + 50 * t + 12], corners[t], 36);
  const TriangleMesh binary = read_mesh_file(file("two_binary.STL", bytes));
  for (const TriangleMesh* mesh : {&ascii, &binary}) {
    ASSERT_EQ(mesh->vertices.size(), 4u);  // the shared corners merged
    ASSERT_EQ(mesh->triangles.size(), 2u);
    EXPECT_EQ(mesh->triangles[1], (std::array<int, 3>{0, 2, 3}));
    EXPECT_EQ(mesh->vertices[3], Eigen::Vector3d(0, 1, 0));
  }
}

TEST_F(MeshFiles, MalformedFilesNameTheFileAndLine) {
  const std::string obj = file("bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
  try {
    read_mesh_file(obj);
    FAIL() << "accepted a face naming vertex 3 of 2";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), obj + ":3: face index 3 names no vertex defined before it");
  }
  EXPECT_THROW(read_mesh_file(file("short.stl", "solid x\n")), std::runtime_error);
  EXPECT_THROW(read_mesh_file(file("mesh.ply", "ply\n")), std::runtime_error);
  // In a scene: at the shape's file key; and a mesh on a moving body is refused at its type.
  const std::string missing = error_of(write(scene("{type: mesh, file: /nonexistent/terrain.obj}", ", inertia: [1, 1, 1]")));
  EXPECT_NE(missing.find("bodies.thing.shapes.body.file: /nonexistent/terrain.obj: cannot be read"), std::string::npos)
      << missing;
  const std::string moving = error_of(write(scene("{type: mesh, file: " + file("ok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n") + "}",
                                                  ", inertia: [1, 1, 1]")));
  EXPECT_NE(moving.find("bodies.thing.shapes.body.type: a mesh can only belong to a fixed body"), std::string::npos)
      << moving;
}

}  // namespace
}  // namespace csim
