// Element tables, outer boundaries and the structured generators: counts, orientation (positive areas
// and volumes, outward face normals), named sets, placement, argument errors.
#include "fem/mesh.h"
#include "fem/mesh_generators.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>

namespace csim {
namespace {

constexpr double kTolerance = 1e-12;

// Signed area (m²) of a plane element by the shoelace formula over its boundary polygon: the corners,
// with each quad8 mid-side node between the corners of its edge.
double signed_area(const Mesh& mesh, int e) {
  const std::vector<int>& element = mesh.elements[e];
  std::vector<int> polygon;
  for (int k = 0; k < 4; ++k) {
    polygon.push_back(element[k]);
    if (mesh.element_type == ElementType::quad8) polygon.push_back(element[4 + k]);
  }
  double twice_area = 0.0;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Eigen::Vector3d& a = mesh.nodes[polygon[k]];
    const Eigen::Vector3d& b = mesh.nodes[polygon[(k + 1) % polygon.size()]];
    twice_area += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * twice_area;
}

// Volume (m³) of a hexa8 with parallel opposite edges: 8 det J at the centre, J = ∂x/∂(ξ, η, ζ).
double hexa_volume(const Mesh& mesh, int e) {
  static constexpr int kSigns[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                       {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero();
  for (int a = 0; a < 8; ++a)
    for (int d = 0; d < 3; ++d) jacobian.col(d) += kSigns[a][d] / 8.0 * mesh.nodes[mesh.elements[e][a]];
  return 8.0 * jacobian.determinant();
}

// Outward normal of a face, scaled by its length (2D) or, for a parallelogram, its area (3D).
Eigen::Vector3d scaled_normal(const Mesh& mesh, const Face& face) {
  const Eigen::Vector3d& x0 = mesh.nodes[face.nodes[0]];
  const Eigen::Vector3d& x1 = mesh.nodes[face.nodes[1]];
  if (mesh.dimension() == 2) {
    const Eigen::Vector3d t = x1 - x0;
    return {t.y(), -t.x(), 0.0};
  }
  return (x1 - x0).cross(mesh.nodes[face.nodes[3]] - x0);
}

Eigen::Vector3d face_centre(const Mesh& mesh, const Face& face) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int node : face.nodes) centre += mesh.nodes[node];
  return centre / static_cast<double>(face.nodes.size());
}

Eigen::Vector3d mesh_centroid(const Mesh& mesh) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& x : mesh.nodes) centre += x;
  return centre / static_cast<double>(mesh.nodes.size());
}

double min_node_distance(const Mesh& mesh) {
  double closest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i)
    for (std::size_t j = i + 1; j < mesh.nodes.size(); ++j)
      closest = std::min(closest, (mesh.nodes[i] - mesh.nodes[j]).norm());
  return closest;
}

void expect_sets_sorted_unique(const Mesh& mesh) {
  for (const auto& [name, nodes] : mesh.node_sets) {
    EXPECT_FALSE(nodes.empty()) << name;
    EXPECT_TRUE(std::is_sorted(nodes.begin(), nodes.end())) << name;
    EXPECT_EQ(std::adjacent_find(nodes.begin(), nodes.end()), nodes.end()) << name;
    for (int node : nodes) EXPECT_TRUE(node >= 0 && node < static_cast<int>(mesh.nodes.size())) << name;
  }
}

void expect_every_node_used(const Mesh& mesh) {
  std::vector<bool> used(mesh.nodes.size(), false);
  for (const auto& element : mesh.elements)
    for (int node : element) used[node] = true;
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
}

// The face set of each side holds the boundary faces whose nodes are all in the node set of that side.
void expect_face_sets_match_node_sets(const Mesh& mesh) {
  for (const auto& [name, faces] : mesh.face_sets) {
    ASSERT_TRUE(mesh.node_sets.count(name)) << name;
    EXPECT_EQ(nodes_of(faces), mesh.node_sets.at(name)) << name;
  }
}

std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const FemError& error) {
    return error.what();
  }
  return "no FemError";
}

// ----- tables and boundaries ------------------------------------------------------------------------

TEST(ElementTypeTest, NodesDimensionAndName) {
  EXPECT_EQ(nodes_per_element(ElementType::quad4), 4);
  EXPECT_EQ(nodes_per_element(ElementType::quad8), 8);
  EXPECT_EQ(nodes_per_element(ElementType::hexa8), 8);
  EXPECT_EQ(mesh_dimension(ElementType::quad4), 2);
  EXPECT_EQ(mesh_dimension(ElementType::quad8), 2);
  EXPECT_EQ(mesh_dimension(ElementType::hexa8), 3);
  EXPECT_STREQ(to_string(ElementType::quad4), "quad4");
  EXPECT_STREQ(to_string(ElementType::quad8), "quad8");
  EXPECT_STREQ(to_string(ElementType::hexa8), "hexa8");
}

TEST(BoundaryFacesTest, UnitSquareQuad8EdgesRunCounterClockwiseWithTheirMidSideNode) {
  Mesh mesh;
  mesh.element_type = ElementType::quad8;
  mesh.nodes = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0, 0}, {1, 0.5, 0}, {0.5, 1, 0}, {0, 0.5, 0}};
  mesh.elements = {{0, 1, 2, 3, 4, 5, 6, 7}};
  const std::vector<Face> faces = boundary_faces(mesh);
  ASSERT_EQ(faces.size(), 4u);
  const std::vector<std::vector<int>> expected = {{0, 1, 4}, {1, 2, 5}, {2, 3, 6}, {3, 0, 7}};
  const Eigen::Vector3d outward[4] = {{0, -1, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
  for (int f = 0; f < 4; ++f) {
    EXPECT_EQ(faces[f].element, 0);
    EXPECT_EQ(faces[f].local_face, f);
    EXPECT_EQ(faces[f].nodes, expected[f]);
    EXPECT_LT((scaled_normal(mesh, faces[f]) - outward[f]).norm(), kTolerance) << "face " << f;
  }
}

TEST(BoundaryFacesTest, UnitCubeFaceNormalsPointOutward) {
  Mesh mesh;
  mesh.element_type = ElementType::hexa8;
  mesh.nodes = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  mesh.elements = {{0, 1, 2, 3, 4, 5, 6, 7}};
  const std::vector<Face> faces = boundary_faces(mesh);
  ASSERT_EQ(faces.size(), 6u);
  const Eigen::Vector3d centre(0.5, 0.5, 0.5);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int f = 0; f < 6; ++f) {
    EXPECT_EQ(faces[f].local_face, f);
    ASSERT_EQ(faces[f].nodes.size(), 4u);
    const Eigen::Vector3d normal = scaled_normal(mesh, faces[f]);
    const Eigen::Vector3d out = face_centre(mesh, faces[f]) - centre;  // half a unit along the axis
    EXPECT_LT((normal - 2.0 * out).norm(), kTolerance) << "face " << f;
    // The four nodes go round the face: consecutive nodes one edge apart.
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR((mesh.nodes[faces[f].nodes[k]] - mesh.nodes[faces[f].nodes[(k + 1) % 4]]).norm(), 1.0, kTolerance);
    sum += normal;
  }
  EXPECT_LT(sum.norm(), kTolerance);
}

TEST(BoundaryFacesTest, SharedFacesAreLeftOutInElementThenFaceOrder) {
  const Mesh mesh = box_mesh(2.0, 1.0, 1.0, 2, 1, 1);
  const std::vector<Face> faces = boundary_faces(mesh);
  ASSERT_EQ(faces.size(), 10u);
  for (std::size_t f = 1; f < faces.size(); ++f)
    EXPECT_LT(std::make_pair(faces[f - 1].element, faces[f - 1].local_face),
              std::make_pair(faces[f].element, faces[f].local_face));
  for (const Face& face : faces) {
    // The face at x = 1 between the two elements is no boundary face.
    const Eigen::Vector3d centre = face_centre(mesh, face);
    EXPECT_FALSE(std::abs(centre.x() - 1.0) < kTolerance && std::abs(centre.y() - 0.5) < kTolerance &&
                 std::abs(centre.z() - 0.5) < kTolerance);
  }
}

TEST(BoundaryFacesTest, RejectsAnElementWithAWrongNode) {
  Mesh mesh;
  mesh.nodes = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  mesh.elements = {{0, 1, 2, 3}};
  EXPECT_NE(error_of([&] { boundary_faces(mesh); }).find("element 0"), std::string::npos);
}

TEST(NodesOfTest, SortedAndUnique) {
  const std::vector<Face> faces = {{0, 0, {5, 2}}, {1, 3, {2, 9}}, {2, 1, {9, 1}}};
  EXPECT_EQ(nodes_of(faces), (std::vector<int>{1, 2, 5, 9}));
  EXPECT_TRUE(nodes_of({}).empty());
}

// ----- rectangle ------------------------------------------------------------------------------------

TEST(RectangleMeshTest, CountsAndPositiveAreas) {
  for (ElementType type : {ElementType::quad4, ElementType::quad8}) {
    const Mesh mesh = rectangle_mesh(2.0, 3.0, 5, 5, type);
    EXPECT_EQ(mesh.element_type, type);
    EXPECT_EQ(mesh.nodes.size(), type == ElementType::quad4 ? 36u : 96u);
    ASSERT_EQ(mesh.elements.size(), 25u);
    double total = 0.0;
    for (int e = 0; e < 25; ++e) {
      EXPECT_NEAR(signed_area(mesh, e), 6.0 / 25.0, kTolerance) << "element " << e;
      total += signed_area(mesh, e);
    }
    EXPECT_NEAR(total, 6.0, kTolerance);
    for (const Eigen::Vector3d& x : mesh.nodes) EXPECT_EQ(x.z(), 0.0);
    EXPECT_GT(min_node_distance(mesh), 0.1);
    expect_every_node_used(mesh);
    expect_sets_sorted_unique(mesh);
    expect_face_sets_match_node_sets(mesh);
  }
  const Mesh thin = rectangle_mesh(1.0, 1.0, 3, 2, ElementType::quad8);
  EXPECT_EQ(thin.nodes.size(), 3u * 7u + 2u * 4u);  // rows of corners and edge midpoints, then of edge midpoints
}

TEST(RectangleMeshTest, Quad8MidSideNodesAtEdgeMidpoints) {
  const Mesh mesh = rectangle_mesh(1.5, 0.5, 3, 2, ElementType::quad8);
  for (const auto& element : mesh.elements)
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d midpoint = 0.5 * (mesh.nodes[element[k]] + mesh.nodes[element[(k + 1) % 4]]);
      EXPECT_LT((mesh.nodes[element[4 + k]] - midpoint).norm(), kTolerance);
    }
}

TEST(RectangleMeshTest, SidesAndCorners) {
  const double width = 2.0, height = 1.0;
  for (ElementType type : {ElementType::quad4, ElementType::quad8}) {
    const Mesh mesh = rectangle_mesh(width, height, 4, 3, type);
    const int per_edge = type == ElementType::quad4 ? 1 : 2;
    auto check_side = [&](const std::string& name, int faces, const std::function<bool(const Eigen::Vector3d&)>& on) {
      ASSERT_TRUE(mesh.node_sets.count(name) && mesh.face_sets.count(name)) << name;
      EXPECT_EQ(mesh.face_sets.at(name).size(), static_cast<std::size_t>(faces)) << name;
      EXPECT_EQ(mesh.node_sets.at(name).size(), static_cast<std::size_t>(per_edge * faces + 1)) << name;
      for (int node : mesh.node_sets.at(name)) EXPECT_TRUE(on(mesh.nodes[node])) << name << " node " << node;
    };
    check_side("bottom", 4, [](const Eigen::Vector3d& x) { return x.y() == 0.0; });
    check_side("top", 4, [&](const Eigen::Vector3d& x) { return x.y() == height; });
    check_side("left", 3, [](const Eigen::Vector3d& x) { return x.x() == 0.0; });
    check_side("right", 3, [&](const Eigen::Vector3d& x) { return x.x() == width; });
    const std::pair<const char*, Eigen::Vector3d> corners[] = {{"bottom_left", {0, 0, 0}},
                                                               {"bottom_right", {width, 0, 0}},
                                                               {"top_left", {0, height, 0}},
                                                               {"top_right", {width, height, 0}}};
    for (const auto& [name, where] : corners) {
      ASSERT_EQ(mesh.node_sets.at(name).size(), 1u) << name;
      EXPECT_EQ(mesh.nodes[mesh.node_sets.at(name)[0]], where) << name;
    }
    EXPECT_EQ(mesh.node_sets.size(), 8u);
    EXPECT_EQ(mesh.face_sets.size(), 4u);
  }
}

TEST(RectangleMeshTest, BoundaryNormalsCloseAndPointOutward) {
  Placement placement;
  placement.angle = 0.4;
  placement.offset = Eigen::Vector3d(-3.0, 2.0, 0.0);
  const Mesh mesh = rectangle_mesh(2.0, 1.0, 4, 3, ElementType::quad4, placement);
  const std::vector<Face> faces = boundary_faces(mesh);
  EXPECT_EQ(faces.size(), 2u * (4 + 3));
  const Eigen::Vector3d centroid = mesh_centroid(mesh);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Face& face : faces) {
    const Eigen::Vector3d normal = scaled_normal(mesh, face);
    EXPECT_GT(normal.dot(face_centre(mesh, face) - centroid), 0.0) << "element " << face.element;
    sum += normal;
  }
  EXPECT_LT(sum.norm(), kTolerance);
  // Each side's faces point the side's way, in the rectangle's own (rotated) frame.
  const Eigen::Vector3d down(std::sin(0.4), -std::cos(0.4), 0.0);
  for (const Face& face : mesh.face_sets.at("bottom"))
    EXPECT_LT((scaled_normal(mesh, face).normalized() - down).norm(), kTolerance);
}

TEST(RectangleMeshTest, PlacementRotatesThenOffsets) {
  Placement placement;
  placement.angle = std::numbers::pi / 6.0;  // 30°
  placement.offset = Eigen::Vector3d(1.0, -2.0, 0.0);
  for (ElementType type : {ElementType::quad4, ElementType::quad8}) {
    const Mesh mesh = rectangle_mesh(2.0, 1.0, 3, 2, type, placement);
    const Eigen::Vector3d bottom_right = mesh.nodes[mesh.node_sets.at("bottom_right").at(0)];
    const Eigen::Vector3d expected(1.0 + 2.0 * std::sqrt(3.0) / 2.0, -2.0 + 2.0 * 0.5, 0.0);
    EXPECT_LT((bottom_right - expected).norm(), 1e-12);
    const Eigen::Vector3d top_left = mesh.nodes[mesh.node_sets.at("top_left").at(0)];
    EXPECT_LT((top_left - Eigen::Vector3d(1.0 - 0.5, -2.0 + std::sqrt(3.0) / 2.0, 0.0)).norm(), 1e-12);
    for (int e = 0; e < static_cast<int>(mesh.elements.size()); ++e)
      EXPECT_NEAR(signed_area(mesh, e), 2.0 / 6.0, kTolerance);
  }
}

TEST(RectangleMeshTest, ErrorsNameTheArgument) {
  EXPECT_NE(error_of([] { rectangle_mesh(0.0, 1.0, 1, 1, ElementType::quad4); }).find("width"), std::string::npos);
  EXPECT_NE(error_of([] { rectangle_mesh(1.0, -1.0, 1, 1, ElementType::quad4); }).find("height"), std::string::npos);
  EXPECT_NE(error_of([] { rectangle_mesh(1.0, std::nan(""), 1, 1, ElementType::quad4); }).find("height"),
            std::string::npos);
  EXPECT_NE(error_of([] { rectangle_mesh(1.0, 1.0, 0, 1, ElementType::quad4); }).find("nx"), std::string::npos);
  EXPECT_NE(error_of([] { rectangle_mesh(1.0, 1.0, 1, -2, ElementType::quad8); }).find("ny"), std::string::npos);
  EXPECT_NE(error_of([] { rectangle_mesh(1.0, 1.0, 1, 1, ElementType::hexa8); }).find("type"), std::string::npos);
  Placement lifted;
  lifted.offset = Eigen::Vector3d(0.0, 0.0, 1.0);
  EXPECT_NE(error_of([&] { rectangle_mesh(1.0, 1.0, 1, 1, ElementType::quad4, lifted); }).find("placement.offset"),
            std::string::npos);
  EXPECT_NE(error_of([] { rectangle_mesh(0.0, 1.0, 1, 1, ElementType::quad4); }).find("rectangle_mesh"),
            std::string::npos);
}

// ----- annulus --------------------------------------------------------------------------------------

TEST(AnnulusMeshTest, CountsPositiveAreasAndNoSeam) {
  const double inner = 0.5, outer = 1.25;
  for (ElementType type : {ElementType::quad4, ElementType::quad8}) {
    const Mesh mesh = annulus_mesh(inner, outer, 12, 3, type);
    EXPECT_EQ(mesh.nodes.size(), type == ElementType::quad4 ? 12u * 4u : 12u * 4u * 2u + 12u * 3u);
    ASSERT_EQ(mesh.elements.size(), 36u);
    double total = 0.0;
    for (int e = 0; e < 36; ++e) {
      EXPECT_GT(signed_area(mesh, e), 0.0) << "element " << e;
      total += signed_area(mesh, e);
    }
    // The polygon of the quad8 nodes is nearer the true ring than that of the corners.
    const double ring = std::numbers::pi * (outer * outer - inner * inner);
    EXPECT_NEAR(total, ring, type == ElementType::quad4 ? 0.06 * ring : 0.015 * ring);
    EXPECT_GT(min_node_distance(mesh), 1e-3);  // also across the seam at θ = 0
    expect_every_node_used(mesh);
    expect_sets_sorted_unique(mesh);
    expect_face_sets_match_node_sets(mesh);
    EXPECT_EQ(boundary_faces(mesh).size(), 24u);  // closed ring: only the two circles
  }
}

TEST(AnnulusMeshTest, CirclesAreExactAndNormalsPointOut) {
  const double inner = 0.3, outer = 0.7;
  for (ElementType type : {ElementType::quad4, ElementType::quad8}) {
    const Mesh mesh = annulus_mesh(inner, outer, 10, 2, type);
    const std::size_t per_circle = type == ElementType::quad4 ? 10u : 20u;
    ASSERT_EQ(mesh.node_sets.at("outer").size(), per_circle);
    ASSERT_EQ(mesh.node_sets.at("inner").size(), per_circle);
    for (int node : mesh.node_sets.at("outer")) EXPECT_NEAR(mesh.nodes[node].norm(), outer, kTolerance);
    for (int node : mesh.node_sets.at("inner")) EXPECT_NEAR(mesh.nodes[node].norm(), inner, kTolerance);
    ASSERT_EQ(mesh.face_sets.at("outer").size(), 10u);
    ASSERT_EQ(mesh.face_sets.at("inner").size(), 10u);
    for (const Face& face : mesh.face_sets.at("outer"))
      EXPECT_GT(scaled_normal(mesh, face).dot(face_centre(mesh, face)), 0.0);
    for (const Face& face : mesh.face_sets.at("inner"))
      EXPECT_LT(scaled_normal(mesh, face).dot(face_centre(mesh, face)), 0.0);
  }
}

TEST(AnnulusMeshTest, Quad8MidSideNodesOnTheArcs) {
  const Mesh mesh = annulus_mesh(1.0, 2.0, 8, 2, ElementType::quad8);
  for (const auto& element : mesh.elements)
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d& a = mesh.nodes[element[k]];
      const Eigen::Vector3d& b = mesh.nodes[element[(k + 1) % 4]];
      const Eigen::Vector3d& mid = mesh.nodes[element[4 + k]];
      if (std::abs(a.norm() - b.norm()) < kTolerance) {
        // An arc: the mid-side node on the same circle, halfway round (on the bisector of a and b).
        EXPECT_NEAR(mid.norm(), a.norm(), kTolerance);
        EXPECT_LT((mid.normalized() - (a + b).normalized()).norm(), kTolerance);
      } else {
        EXPECT_LT((mid - 0.5 * (a + b)).norm(), kTolerance);  // a radial segment
      }
    }
}

TEST(AnnulusMeshTest, PlacementMovesTheCentre) {
  Placement placement;
  placement.angle = 1.0;
  placement.offset = Eigen::Vector3d(4.0, 5.0, 0.0);
  const Mesh mesh = annulus_mesh(1.0, 2.0, 6, 1, ElementType::quad8, placement);
  for (int node : mesh.node_sets.at("outer"))
    EXPECT_NEAR((mesh.nodes[node] - placement.offset).norm(), 2.0, kTolerance);
  for (int e = 0; e < static_cast<int>(mesh.elements.size()); ++e) EXPECT_GT(signed_area(mesh, e), 0.0);
}

TEST(AnnulusMeshTest, ErrorsNameTheArgument) {
  EXPECT_NE(error_of([] { annulus_mesh(0.0, 1.0, 8, 1, ElementType::quad4); }).find("inner_radius"),
            std::string::npos);
  EXPECT_NE(error_of([] { annulus_mesh(1.0, -1.0, 8, 1, ElementType::quad4); }).find("outer_radius"),
            std::string::npos);
  const std::string reversed = error_of([] { annulus_mesh(2.0, 1.0, 8, 1, ElementType::quad4); });
  EXPECT_NE(reversed.find("inner_radius must be < outer_radius"), std::string::npos) << reversed;
  EXPECT_NE(error_of([] { annulus_mesh(1.0, 2.0, 2, 1, ElementType::quad4); }).find("n_circumferential"),
            std::string::npos);
  EXPECT_NE(error_of([] { annulus_mesh(1.0, 2.0, 8, 0, ElementType::quad4); }).find("n_radial"), std::string::npos);
  EXPECT_NE(error_of([] { annulus_mesh(1.0, 2.0, 8, 1, ElementType::hexa8); }).find("type"), std::string::npos);
}

// ----- annulus, 3D ----------------------------------------------------------------------------------

// det J (m³ per unit reference volume) of a hexa8 at (ξ, η, ζ), from the trilinear shape functions.
double hexa_jacobian(const Mesh& mesh, int e, double xi, double eta, double zeta) {
  static constexpr int kSigns[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                       {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const double at[3] = {xi, eta, zeta};
  Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero();
  for (int a = 0; a < 8; ++a)
    for (int d = 0; d < 3; ++d) {
      double derivative = kSigns[a][d] / 8.0;  // ∂N_a/∂(ξ, η, ζ)_d, N_a = Π (1 + s_k x_k) / 8
      for (int k = 0; k < 3; ++k)
        if (k != d) derivative *= 1.0 + kSigns[a][k] * at[k];
      jacobian.col(d) += derivative * mesh.nodes[mesh.elements[e][a]];
    }
  return jacobian.determinant();
}

// The volume (m³) of a hexa8 by 2 × 2 × 2 Gauss points (exact for the trilinear map's det J, which has
// degree 2 in each coordinate), checking that det J > 0 at each of them and at the corners.
double checked_hexa_volume(const Mesh& mesh, int e) {
  const double g = 1.0 / std::sqrt(3.0);
  double volume = 0.0;
  for (double xi : {-g, g})
    for (double eta : {-g, g})
      for (double zeta : {-g, g}) {
        const double det = hexa_jacobian(mesh, e, xi, eta, zeta);
        EXPECT_GT(det, 0.0) << "element " << e;
        volume += det;
      }
  for (double xi : {-1.0, 1.0})
    for (double eta : {-1.0, 1.0})
      for (double zeta : {-1.0, 1.0}) EXPECT_GT(hexa_jacobian(mesh, e, xi, eta, zeta), 0.0) << "element " << e;
  return volume;
}

TEST(Annulus3dMeshTest, CountsJacobiansAndPolygonVolume) {
  const double inner = 0.5, outer = 1.25, width = 0.3;
  const int n_c = 12, n_r = 3, n_a = 2;
  const Mesh mesh = annulus_mesh_3d(inner, outer, width, n_c, n_r, n_a);
  EXPECT_EQ(mesh.element_type, ElementType::hexa8);
  EXPECT_EQ(mesh.nodes.size(), static_cast<std::size_t>(n_c * (n_r + 1) * (n_a + 1)));
  ASSERT_EQ(mesh.elements.size(), static_cast<std::size_t>(n_c * n_r * n_a));
  double total = 0.0;
  for (int e = 0; e < static_cast<int>(mesh.elements.size()); ++e) total += checked_hexa_volume(mesh, e);
  // The quad4 ring is exactly the area between two regular n_c-gons; the prism over it has that area × w.
  const double polygon = n_c / 2.0 * std::sin(2.0 * std::numbers::pi / n_c) * (outer * outer - inner * inner);
  EXPECT_NEAR(total, polygon * width, 1e-12);
  EXPECT_GT(min_node_distance(mesh), 1e-3);  // the seam at θ = 0 shares its nodes, in every layer
  expect_every_node_used(mesh);
  expect_sets_sorted_unique(mesh);
  expect_face_sets_match_node_sets(mesh);
  EXPECT_EQ(boundary_faces(mesh).size(), static_cast<std::size_t>(2 * n_c * n_a + 2 * n_c * n_r));
}

TEST(Annulus3dMeshTest, LayersFollowThePlaneAnnulus) {
  const Mesh plane = annulus_mesh(1.0, 2.0, 8, 2, ElementType::quad4);
  const Mesh mesh = annulus_mesh_3d(1.0, 2.0, 0.5, 8, 2, 3);
  const int per_layer = static_cast<int>(plane.nodes.size());
  const int per_layer_elements = static_cast<int>(plane.elements.size());
  for (int k = 0; k <= 3; ++k)
    for (int node = 0; node < per_layer; ++node) {
      const Eigen::Vector3d& x = mesh.nodes[k * per_layer + node];
      EXPECT_EQ(x.x(), plane.nodes[node].x());
      EXPECT_EQ(x.y(), plane.nodes[node].y());
      EXPECT_NEAR(x.z(), -0.25 + 0.5 * k / 3.0, kTolerance);
    }
  for (int k = 0; k < 3; ++k)
    for (int e = 0; e < per_layer_elements; ++e)
      for (int corner = 0; corner < 4; ++corner) {
        EXPECT_EQ(mesh.elements[k * per_layer_elements + e][corner], plane.elements[e][corner] + k * per_layer);
        EXPECT_EQ(mesh.elements[k * per_layer_elements + e][corner + 4],
                  plane.elements[e][corner] + (k + 1) * per_layer);
      }
}

TEST(Annulus3dMeshTest, SetsAndOutwardNormals) {
  const double inner = 0.3, outer = 0.7, width = 0.2;
  const int n_c = 10, n_r = 2, n_a = 3;
  const Mesh mesh = annulus_mesh_3d(inner, outer, width, n_c, n_r, n_a);
  auto radius = [](const Eigen::Vector3d& x) { return std::hypot(x.x(), x.y()); };
  const struct {
    const char* name;
    std::size_t faces, nodes;
  } sides[] = {{"inner", n_c * n_a, n_c * (n_a + 1)},
               {"outer", n_c * n_a, n_c * (n_a + 1)},
               {"zmin", n_c * n_r, n_c * (n_r + 1)},
               {"zmax", n_c * n_r, n_c * (n_r + 1)}};
  for (const auto& side : sides) {
    ASSERT_TRUE(mesh.face_sets.count(side.name) && mesh.node_sets.count(side.name)) << side.name;
    EXPECT_EQ(mesh.face_sets.at(side.name).size(), side.faces) << side.name;
    EXPECT_EQ(mesh.node_sets.at(side.name).size(), side.nodes) << side.name;
  }
  for (int node : mesh.node_sets.at("inner")) EXPECT_NEAR(radius(mesh.nodes[node]), inner, kTolerance);
  for (int node : mesh.node_sets.at("outer")) EXPECT_NEAR(radius(mesh.nodes[node]), outer, kTolerance);
  for (int node : mesh.node_sets.at("zmin")) EXPECT_EQ(mesh.nodes[node].z(), -width / 2.0);
  for (int node : mesh.node_sets.at("zmax")) EXPECT_EQ(mesh.nodes[node].z(), width / 2.0);
  std::vector<int> every(mesh.nodes.size());
  for (int node = 0; node < static_cast<int>(every.size()); ++node) every[node] = node;
  EXPECT_EQ(mesh.node_sets.at("all"), every);
  EXPECT_EQ(mesh.node_sets.size(), 5u);
  EXPECT_EQ(mesh.face_sets.size(), 4u);

  // Outward: away from the axis on "outer", towards it on "inner", along ∓z on the end faces.
  for (const Face& face : mesh.face_sets.at("outer")) {
    const Eigen::Vector3d centre = face_centre(mesh, face);
    EXPECT_GT(scaled_normal(mesh, face).dot(Eigen::Vector3d(centre.x(), centre.y(), 0.0)), 0.0);
  }
  for (const Face& face : mesh.face_sets.at("inner")) {
    const Eigen::Vector3d centre = face_centre(mesh, face);
    EXPECT_LT(scaled_normal(mesh, face).dot(Eigen::Vector3d(centre.x(), centre.y(), 0.0)), 0.0);
  }
  for (const Face& face : mesh.face_sets.at("zmin"))
    EXPECT_LT((scaled_normal(mesh, face).normalized() - Eigen::Vector3d(0, 0, -1)).norm(), kTolerance);
  for (const Face& face : mesh.face_sets.at("zmax"))
    EXPECT_LT((scaled_normal(mesh, face).normalized() - Eigen::Vector3d(0, 0, 1)).norm(), kTolerance);
}

TEST(Annulus3dMeshTest, OneLayerAndPlacement) {
  Placement placement;
  placement.angle = 0.7;
  placement.offset = Eigen::Vector3d(1.0, -2.0, 0.5);  // z allowed: the mesh is not plane
  const Mesh mesh = annulus_mesh_3d(1.0, 2.0, 0.4, 16, 2, 1, placement);
  EXPECT_EQ(mesh.nodes.size(), 16u * 3u * 2u);
  ASSERT_EQ(mesh.elements.size(), 32u);
  for (int node : mesh.node_sets.at("outer")) {
    const Eigen::Vector3d relative = mesh.nodes[node] - placement.offset;
    EXPECT_NEAR(std::hypot(relative.x(), relative.y()), 2.0, kTolerance);
  }
  for (int node : mesh.node_sets.at("zmin")) EXPECT_NEAR(mesh.nodes[node].z(), 0.3, kTolerance);
  for (int node : mesh.node_sets.at("zmax")) EXPECT_NEAR(mesh.nodes[node].z(), 0.7, kTolerance);
  for (int e = 0; e < 32; ++e) checked_hexa_volume(mesh, e);
}

TEST(Annulus3dMeshTest, ErrorsNameTheFunctionAndArgument) {
  auto error = [](const std::function<void()>& action, const std::string& argument) {
    const std::string message = error_of(action);
    EXPECT_NE(message.find("annulus_mesh_3d"), std::string::npos) << message;
    EXPECT_NE(message.find(argument), std::string::npos) << message;
  };
  error([] { annulus_mesh_3d(0.0, 1.0, 0.1, 8, 1, 1); }, "inner_radius");
  error([] { annulus_mesh_3d(1.0, -1.0, 0.1, 8, 1, 1); }, "outer_radius");
  error([] { annulus_mesh_3d(2.0, 1.0, 0.1, 8, 1, 1); }, "inner_radius must be < outer_radius");
  error([] { annulus_mesh_3d(1.0, 2.0, 0.0, 8, 1, 1); }, "width");
  error([] { annulus_mesh_3d(1.0, 2.0, -0.1, 8, 1, 1); }, "width");
  error([] { annulus_mesh_3d(1.0, 2.0, INFINITY, 8, 1, 1); }, "width");
  error([] { annulus_mesh_3d(1.0, 2.0, std::nan(""), 8, 1, 1); }, "width");
  error([] { annulus_mesh_3d(1.0, 2.0, 0.1, 2, 1, 1); }, "n_circumferential");
  error([] { annulus_mesh_3d(1.0, 2.0, 0.1, 8, 0, 1); }, "n_radial");
  error([] { annulus_mesh_3d(1.0, 2.0, 0.1, 8, 1, 0); }, "n_axial");
  Placement bad;
  bad.offset = Eigen::Vector3d(0.0, 0.0, std::nan(""));
  error([&] { annulus_mesh_3d(1.0, 2.0, 0.1, 8, 1, 1, bad); }, "placement.offset");
}

// ----- box ------------------------------------------------------------------------------------------

TEST(BoxMeshTest, CountsAndVolumes) {
  const Mesh mesh = box_mesh(1.0, 2.0, 3.0, 2, 3, 4);
  EXPECT_EQ(mesh.element_type, ElementType::hexa8);
  EXPECT_EQ(mesh.nodes.size(), 3u * 4u * 5u);
  ASSERT_EQ(mesh.elements.size(), 24u);
  for (int e = 0; e < 24; ++e) EXPECT_NEAR(hexa_volume(mesh, e), 6.0 / 24.0, kTolerance) << "element " << e;
  EXPECT_GT(min_node_distance(mesh), 0.4);
  expect_sets_sorted_unique(mesh);
  expect_face_sets_match_node_sets(mesh);
  EXPECT_EQ(boundary_faces(mesh).size(), 2u * (2 * 3 + 3 * 4 + 2 * 4));
}

TEST(BoxMeshTest, SidesCornersAndOutwardNormals) {
  const double lx = 1.0, ly = 2.0, lz = 3.0;
  const Mesh mesh = box_mesh(lx, ly, lz, 2, 3, 4);
  ASSERT_EQ(mesh.face_sets.size(), 6u);
  const struct {
    const char* name;
    std::size_t faces, nodes;
    Eigen::Vector3d normal;
  } sides[] = {{"xmin", 12, 20, {-1, 0, 0}}, {"xmax", 12, 20, {1, 0, 0}}, {"ymin", 8, 15, {0, -1, 0}},
               {"ymax", 8, 15, {0, 1, 0}},   {"zmin", 6, 12, {0, 0, -1}}, {"zmax", 6, 12, {0, 0, 1}}};
  for (const auto& side : sides) {
    ASSERT_EQ(mesh.face_sets.at(side.name).size(), side.faces) << side.name;
    EXPECT_EQ(mesh.node_sets.at(side.name).size(), side.nodes) << side.name;
    for (const Face& face : mesh.face_sets.at(side.name))
      EXPECT_LT((scaled_normal(mesh, face).normalized() - side.normal).norm(), kTolerance) << side.name;
  }
  for (int cx = 0; cx <= 1; ++cx)
    for (int cy = 0; cy <= 1; ++cy)
      for (int cz = 0; cz <= 1; ++cz) {
        const std::string name = "x" + std::to_string(cx) + "y" + std::to_string(cy) + "z" + std::to_string(cz);
        ASSERT_EQ(mesh.node_sets.at(name).size(), 1u) << name;
        EXPECT_EQ(mesh.nodes[mesh.node_sets.at(name)[0]], Eigen::Vector3d(cx * lx, cy * ly, cz * lz)) << name;
      }
  EXPECT_EQ(mesh.node_sets.size(), 14u);
}

TEST(BoxMeshTest, PlacementKeepsOrientation) {
  Placement placement;
  placement.angle = -2.0;
  placement.offset = Eigen::Vector3d(0.5, 0.25, -1.0);
  const Mesh mesh = box_mesh(1.0, 1.0, 1.0, 2, 2, 2, placement);
  for (int e = 0; e < 8; ++e) EXPECT_NEAR(hexa_volume(mesh, e), 0.125, kTolerance);
  const Eigen::Vector3d corner = mesh.nodes[mesh.node_sets.at("x1y0z1").at(0)];
  EXPECT_LT((corner - Eigen::Vector3d(0.5 + std::cos(-2.0), 0.25 + std::sin(-2.0), 0.0)).norm(), kTolerance);
  for (const Face& face : mesh.face_sets.at("zmin"))
    EXPECT_LT((scaled_normal(mesh, face).normalized() - Eigen::Vector3d(0, 0, -1)).norm(), kTolerance);
}

TEST(BoxMeshTest, ErrorsNameTheArgument) {
  EXPECT_NE(error_of([] { box_mesh(0.0, 1.0, 1.0, 1, 1, 1); }).find("lx"), std::string::npos);
  EXPECT_NE(error_of([] { box_mesh(1.0, -1.0, 1.0, 1, 1, 1); }).find("ly"), std::string::npos);
  EXPECT_NE(error_of([] { box_mesh(1.0, 1.0, INFINITY, 1, 1, 1); }).find("lz"), std::string::npos);
  EXPECT_NE(error_of([] { box_mesh(1.0, 1.0, 1.0, 0, 1, 1); }).find("nx"), std::string::npos);
  EXPECT_NE(error_of([] { box_mesh(1.0, 1.0, 1.0, 1, 0, 1); }).find("ny"), std::string::npos);
  EXPECT_NE(error_of([] { box_mesh(1.0, 1.0, 1.0, 1, 1, 0); }).find("nz"), std::string::npos);
  Placement bad;
  bad.angle = std::nan("");
  EXPECT_NE(error_of([&] { box_mesh(1.0, 1.0, 1.0, 1, 1, 1, bad); }).find("placement.angle"), std::string::npos);
}

}  // namespace
}  // namespace csim
