// Helpers of the detection tests: poses, a detection between two placed shapes through CollisionWorld
// (in both registration orders), and the contact_point.h conventions every contact must satisfy.
#pragma once

#include "contact/collision_world.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <vector>

namespace csim::detection_test {

constexpr double kExact = 1e-12;  // m, closed forms
constexpr double kFcl = 1e-9;     // m, FCL queries
constexpr double kPi = 3.14159265358979323846;

inline Eigen::Isometry3d translation(double x, double y, double z) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() << x, y, z;
  return pose;
}

inline Eigen::Isometry3d rotation(double angle, const Eigen::Vector3d& axis) {
  return Eigen::Isometry3d(Eigen::AngleAxisd(angle, axis.normalized()));
}

// A generic rigid motion applied to whole 3D scenes so that no test relies on world axes.
inline const Eigen::Isometry3d kScene = translation(0.3, -0.7, 1.1) * rotation(0.7, {1, 2, 3});

inline void expect_near(const Eigen::Vector3d& actual, const Eigen::Vector3d& expected, double tol) {
  EXPECT_LE((actual - expected).norm(), tol) << "actual   " << actual.transpose()
                                             << "\nexpected " << expected.transpose();
}

// (n, t1, t2) orthonormal and right-handed.
inline void expect_frame(const ContactPoint& c) {
  EXPECT_NEAR(c.normal.norm(), 1.0, 1e-12);
  EXPECT_NEAR(c.t1.norm(), 1.0, 1e-12);
  EXPECT_NEAR(c.t2.norm(), 1.0, 1e-12);
  EXPECT_NEAR(c.normal.dot(c.t1), 0.0, 1e-12);
  EXPECT_NEAR(c.normal.dot(c.t2), 0.0, 1e-12);
  EXPECT_NEAR(c.t1.dot(c.t2), 0.0, 1e-12);
  expect_near(c.normal.cross(c.t1), c.t2, 1e-12);  // right-handed
}

// The contact_point.h conventions that hold for every detected contact.
inline void expect_well_formed(const ContactPoint& c, double tol) {
  expect_frame(c);
  expect_near(c.point_b - c.point_a, c.gap * c.normal, tol);
  EXPECT_LT(c.key.object_a, c.key.object_b);
}

struct Placed {
  Shape shape;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  bool fixed = false;
};

// Detects between `first` and `second` (bodies 0 and 1); `reversed` registers second first, so ids
// and hence the A/B roles swap.
inline std::vector<ContactPoint> detect(const Placed& first, const Placed& second, double margin,
                                 bool reversed = false, bool planar = false) {
  CollisionWorld world(planar);
  const Placed& x = reversed ? second : first;
  const Placed& y = reversed ? first : second;
  const int ix = world.add_object(0, x.shape, x.fixed);
  const int iy = world.add_object(1, y.shape, y.fixed);
  world.set_pose(ix, x.pose);
  world.set_pose(iy, y.pose);
  world.update(margin);
  std::vector<ContactPoint> contacts;
  world.find_contacts(contacts);
  for (const ContactPoint& c : contacts) expect_well_formed(c, 1e-9);
  return contacts;
}

// Expected physics of one contact, normal from `first` to `second`.
struct Expected {
  double gap;
  Eigen::Vector3d normal;
  Eigen::Vector3d on_first;
  Eigen::Vector3d on_second;
};

// Checks one contact in both registration orders: same gap, flipped normal, swapped points.
inline void expect_single_contact(const Placed& first, const Placed& second, double margin,
                           const Expected& e, double tol, bool check_points = true,
                           bool planar = false) {
  for (bool reversed : {false, true}) {
    SCOPED_TRACE(reversed ? "ids swapped" : "ids in order");
    const auto contacts = detect(first, second, margin, reversed, planar);
    ASSERT_EQ(contacts.size(), 1u);
    const ContactPoint& c = contacts[0];
    // Feature 0, or a box–box manifold's vertex 0 with the reference face on B (convex_manifold.h).
    EXPECT_EQ(c.key.object_a, 0);
    EXPECT_EQ(c.key.object_b, 1);
    EXPECT_EQ(c.key.feature % 128, 0);
    EXPECT_NEAR(c.gap, e.gap, tol);
    expect_near(c.normal, reversed ? Eigen::Vector3d(-e.normal) : e.normal, tol);
    if (check_points) {
      expect_near(reversed ? c.point_b : c.point_a, e.on_first, tol);
      expect_near(reversed ? c.point_a : c.point_b, e.on_second, tol);
    }
  }
}

inline void expect_no_contact(const Placed& first, const Placed& second, double margin, bool planar = false) {
  EXPECT_TRUE(detect(first, second, margin, false, planar).empty());
  EXPECT_TRUE(detect(first, second, margin, true, planar).empty());
}

}  // namespace csim::detection_test
