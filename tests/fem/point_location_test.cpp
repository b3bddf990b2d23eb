// locate_point and interpolate (fem/point_location.h) against fields the elements reproduce exactly:
// an isoparametric element interpolates a field linear in x exactly whatever its shape (Σ N_a = 1 and
// Σ N_a x_a = x), and on undistorted rectangles and bricks the bilinear xy (quad4, quad8) and the
// trilinear xyz (hexa8) as well (Zienkiewicz & Taylor vol. 1, §9.3 and ch. 10).
#include "fem/point_location.h"

#include "tests/fem/test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

namespace csim {
namespace {

const ElementType kTypes[] = {ElementType::quad4, ElementType::quad8, ElementType::hexa8};

// 3 × 2 (× 2) elements on [0, 1.5] × [0, 1] (× [0, 0.8]) m, the interior nodes optionally moved
// (curved interior edges for quad8): the body stays the rectangle or the box.
Mesh block(ElementType type, bool distorted) {
  Mesh mesh = type == ElementType::hexa8 ? test::box(3, 2, 2, 1.5, 1.0, 0.8) : test::rectangle(type, 3, 2, 1.5, 1.0);
  if (distorted) test::distort(mesh, 0.08, true);
  return mesh;
}

// Points spread through the body (and on its faces), deterministically.
std::vector<Eigen::Vector3d> points_in(ElementType type) {
  std::vector<Eigen::Vector3d> points;
  const bool solid = type == ElementType::hexa8;
  for (int k = 0; k < 37; ++k) {
    const double s = std::fmod(0.618034 * k, 1.0), t = std::fmod(0.381966 * k + 0.1, 1.0);
    const double u = std::fmod(0.7548777 * k + 0.05, 1.0);
    points.emplace_back(1.5 * s, 1.0 * t, solid ? 0.8 * u : 0.0);
  }
  points.emplace_back(1.5, 0.37, solid ? 0.8 : 0.0);  // on the boundary
  points.emplace_back(0.5, 0.5, solid ? 0.4 : 0.0);   // on element faces shared inside
  return points;
}

// A nodal field sampled from f (d components a node) and its interpolation at each point, against f.
void expect_reproduced(const Mesh& mesh, const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& f,
                       const std::vector<Eigen::Vector3d>& points) {
  const int d = mesh.dofs_per_node();
  Eigen::VectorXd values(mesh.dof_count()), positions(mesh.dof_count());
  for (std::size_t n = 0; n < mesh.nodes.size(); ++n) {
    values.segment(d * n, d) = f(mesh.nodes[n]).head(d);
    positions.segment(d * n, d) = mesh.nodes[n].head(d);
  }
  for (const Eigen::Vector3d& x : points) {
    const std::optional<MeshPoint> point = locate_point(mesh, x);
    ASSERT_TRUE(point) << to_string(mesh.element_type) << " at " << x.transpose();
    EXPECT_LE(point->natural.cwiseAbs().maxCoeff(), 1.0);
    double sum = 0.0;
    for (int a = 0; a < point->count; ++a) sum += point->weights[a];
    EXPECT_NEAR(sum, 1.0, 1e-14);
    // The located point is x (the map inverted), and the field's value there is f(x).
    EXPECT_LE((interpolate(mesh, *point, positions) - x).norm(), 1e-12) << x.transpose();
    EXPECT_LE((interpolate(mesh, *point, values) - f(x)).norm(), 1e-12) << x.transpose();
  }
}

TEST(PointLocation, LinearFieldsAreExactInDistortedElements) {
  for (ElementType type : kTypes) {
    const Mesh mesh = block(type, true);
    const bool solid = type == ElementType::hexa8;
    expect_reproduced(
        mesh,
        [solid](const Eigen::Vector3d& x) {
          return Eigen::Vector3d(0.1 + 2.0 * x.x() - 0.5 * x.y() + 0.3 * x.z(), -0.2 + 0.7 * x.x() + 1.3 * x.y(),
                                 solid ? 0.4 - x.x() + 0.25 * x.z() : 0.0);
        },
        points_in(type));
  }
}

TEST(PointLocation, BilinearFieldsAreExactInRegularElements) {
  for (ElementType type : kTypes) {
    const Mesh mesh = block(type, false);
    const bool solid = type == ElementType::hexa8;
    expect_reproduced(
        mesh,
        [solid](const Eigen::Vector3d& x) {
          return Eigen::Vector3d(x.x() * x.y() + (solid ? x.x() * x.y() * x.z() : 0.0), 1.0 - 3.0 * x.x() * x.y(),
                                 solid ? x.y() * x.z() : 0.0);
        },
        points_in(type));
  }
}

TEST(PointLocation, ANodeIsItsOwnPointAndAPointOutsideIsNone) {
  for (ElementType type : kTypes) {
    const Mesh mesh = block(type, true);
    const bool solid = type == ElementType::hexa8;
    // A node: weight 1 on it, 0 on the others.
    const int node = mesh.element_type == ElementType::hexa8 ? 13 : 5;
    const std::optional<MeshPoint> at_node = locate_point(mesh, mesh.nodes[node]);
    ASSERT_TRUE(at_node);
    for (int a = 0; a < at_node->count; ++a)
      EXPECT_NEAR(at_node->weights[a], at_node->nodes[a] == node ? 1.0 : 0.0, 1e-12);
    for (const Eigen::Vector3d& outside :
         {Eigen::Vector3d(1.5 + 1e-6, 0.5, solid ? 0.4 : 0.0), Eigen::Vector3d(-0.3, 0.5, 0.0),
          Eigen::Vector3d(0.7, 1.0 + 1e-6, solid ? 0.4 : 0.0), Eigen::Vector3d(5.0, 5.0, 0.0)})
      EXPECT_FALSE(locate_point(mesh, outside)) << to_string(type) << " at " << outside.transpose();
    if (solid) {
      EXPECT_FALSE(locate_point(mesh, Eigen::Vector3d(0.7, 0.5, 0.8 + 1e-6)));
    }
  }
}

}  // namespace
}  // namespace csim
