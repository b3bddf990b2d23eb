// Collision shapes in their body's frame (metres). A shape is attached to a body at a local pose.
#pragma once

#include <Eigen/Geometry>
#include <variant>

namespace csim {

struct Sphere {
  double radius = 0.0;  // m, > 0 (in a plane scene: a disk of that radius in z = 0)
};

struct Box {
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  // m, > 0 (plane scenes: z extent is the depth)
};

// The solid { x : n·x ≤ offset } in the shape frame: material below the boundary plane, outward
// normal n (unit). Used for grounds and walls; always on a fixed body.
struct Halfspace {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;  // m
};

using Shape = std::variant<Sphere, Box, Halfspace>;

}  // namespace csim
