#include "engine/springs.h"

#include "engine/linear_algebra/same_bits.h"

#include <algorithm>
#include <array>

namespace csim {

namespace {

bool rotates(const Body& body) { return !body.rotation_axes().empty(); }

Eigen::Matrix3d projector(const Eigen::Vector3d& direction) {
  if (direction.isZero()) return Eigen::Matrix3d::Identity();
  return direction * direction.transpose();
}

// The (global index, column) entries of a spring's Jacobian J = J_a − J_b, at most nine per end: a
// fixed-size list.
struct Entry {  // not initialized: only the first `count` of an Entries are written and read
  int index;
  Eigen::Vector3d column;
};
struct Entries {
  std::array<Entry, 18> entry;
  int count = 0;
  const Entry* begin() const { return entry.data(); }
  const Entry* end() const { return entry.data() + count; }
};

}  // namespace

Springs::Springs(const World& world) : world_(world) {
  // A body's orientation coordinates: its positions that are not the coordinate of a translation
  // (a plane body's angle, a rigid body's quaternion).
  auto add_orientation_coordinates = [&](const BodyInstance& b) {
    std::vector<bool> translation(b.body->position_size(), false);
    const auto axes = b.body->rotation_axes();
    for (int c = 0; c < b.body->velocity_size(); ++c) {
      const bool rotation = std::any_of(axes.begin(), axes.end(), [c](const auto& axis) { return axis.first == c; });
      if (const int coordinate = b.body->coordinate_of(c); !rotation && coordinate >= 0) translation[coordinate] = true;
    }
    for (int p = 0; p < b.body->position_size(); ++p)
      if (!translation[p]) stiffness_coordinates_.push_back(b.position_offset + p);
  };
  for (const Spring& s : world.springs) {
    projectors_.push_back(projector(s.direction));
    const BodyInstance& a = world.bodies[s.body_a];
    reference_points_a_.push_back(a.body->point_world(a.reference_position, s.point_a));
    if (s.body_b >= 0) {
      const BodyInstance& b = world.bodies[s.body_b];
      reference_points_b_.push_back(b.body->point_world(b.reference_position, s.point_b));
    } else {
      reference_points_b_.push_back(Eigen::Vector3d::Zero());
    }
    if (rotates(*a.body) && !s.point_a.isZero()) add_orientation_coordinates(a);
    if (s.body_b >= 0 && rotates(*world.bodies[s.body_b].body) && !s.point_b.isZero())
      add_orientation_coordinates(world.bodies[s.body_b]);
  }
  std::sort(stiffness_coordinates_.begin(), stiffness_coordinates_.end());
  stiffness_coordinates_.erase(std::unique(stiffness_coordinates_.begin(), stiffness_coordinates_.end()),
                               stiffness_coordinates_.end());
  kept_.ends.resize(2 * world.springs.size());
  kept_.elongations.resize(world.springs.size());
}

const Springs::Evaluation& Springs::at(const Vector& q) const {
  Evaluation& e = kept_;
  // The same bits, not merely equal values: −0 and +0 may give zeros of other signs.
  if (e.positions.size() == q.size() && same_bits(q.data(), e.positions.data(), q.size()))
    return e;
  for (std::size_t i = 0; i < world_.springs.size(); ++i) {
    const Spring& s = world_.springs[i];
    End& end_a = e.ends[2 * i];
    End& end_b = e.ends[2 * i + 1];
    const BodyInstance& a = world_.bodies[s.body_a];
    end_a.offset = a.velocity_offset;
    Eigen::Vector3d d = a.body->point_kinematics(a.positions(q), s.point_a, end_a.jacobian) - reference_points_a_[i];
    end_b.jacobian.count = 0;
    if (s.body_b >= 0) {
      const BodyInstance& b = world_.bodies[s.body_b];
      end_b.offset = b.velocity_offset;
      d -= b.body->point_kinematics(b.positions(q), s.point_b, end_b.jacobian) - reference_points_b_[i];
    }
    e.elongations[i].noalias() = projectors_[i] * d;
    const Eigen::Vector3d force_on_a = -s.stiffness * e.elongations[i];
    for (int k = 0; k < end_a.jacobian.count; ++k) end_a.force[k] = end_a.jacobian.column.col(k).dot(force_on_a);
    // −(j·F_a) on b: f + (−x) is f − x to the bit.
    for (int k = 0; k < end_b.jacobian.count; ++k) end_b.force[k] = -end_b.jacobian.column.col(k).dot(force_on_a);
  }
  e.positions = q;
  return e;
}

void Springs::add_forces(const Vector& q, Vector& f) const {
  if (empty()) return;
  for (const End& end : at(q).ends)
    for (int k = 0; k < end.jacobian.count; ++k) f(end.offset + end.jacobian.index[k]) += end.force[k];
}

void Springs::add_energy(const Vector& q, double& energy) const {
  if (empty()) return;
  const Evaluation& e = at(q);
  for (std::size_t i = 0; i < world_.springs.size(); ++i)
    energy += 0.5 * world_.springs[i].stiffness * e.elongations[i].squaredNorm();
}

void Springs::jacobian_columns(const Vector& q, std::vector<double>& columns) const {
  columns.clear();
  if (empty()) return;
  for (const End& end : at(q).ends)
    columns.insert(columns.end(), end.jacobian.column.data(), end.jacobian.column.data() + 3 * end.jacobian.count);
}

// The same bits: those give the same K to the bit (equal values alone would not, −0 against +0).
bool Springs::same_jacobian_columns(const Vector& q, const std::vector<double>& columns) const {
  if (empty()) return columns.empty();
  std::size_t size = 0;
  for (const End& end : at(q).ends) {
    const std::size_t length = 3 * end.jacobian.count;
    if (size + length > columns.size() ||
        !same_bits(end.jacobian.column.data(), columns.data() + size, length))
      return false;
    size += length;
  }
  return size == columns.size();
}

namespace {

Entries entries_of(const PointJacobian& a, int offset_a, const PointJacobian& b, int offset_b) {
  Entries entries;
  for (int k = 0; k < a.count; ++k) entries.entry[entries.count++] = {offset_a + a.index[k], a.column.col(k)};
  for (int k = 0; k < b.count; ++k) entries.entry[entries.count++] = {offset_b + b.index[k], -b.column.col(k)};
  return entries;
}

}  // namespace

void Springs::add_stiffness(const Vector& q, Triplets& K) const {
  if (empty()) return;
  const Evaluation& e = at(q);
  for (std::size_t i = 0; i < world_.springs.size(); ++i) {
    const End &a = e.ends[2 * i], &b = e.ends[2 * i + 1];
    const Entries entries = entries_of(a.jacobian, a.offset, b.jacobian, b.offset);
    const Eigen::Matrix3d& P = projectors_[i];
    for (const Entry& row : entries)
      for (const Entry& column : entries) {
        const double value = world_.springs[i].stiffness * row.column.dot(P * column.column);
        if (value != 0.0) K.emplace_back(row.index, column.index, value);
      }
  }
}

void Springs::add_stiffness_product(const Vector& q, const Vector& v, Vector& out) const {
  if (empty()) return;
  const Evaluation& e = at(q);
  for (std::size_t i = 0; i < world_.springs.size(); ++i) {
    const End &a = e.ends[2 * i], &b = e.ends[2 * i + 1];
    Eigen::Vector3d relative_velocity = Eigen::Vector3d::Zero();  // J v = J_a v − J_b v (m/s)
    for (int k = 0; k < a.jacobian.count; ++k) relative_velocity += a.jacobian.column.col(k) * v(a.offset + a.jacobian.index[k]);
    for (int k = 0; k < b.jacobian.count; ++k) relative_velocity -= b.jacobian.column.col(k) * v(b.offset + b.jacobian.index[k]);
    const Eigen::Vector3d force = world_.springs[i].stiffness * (projectors_[i] * relative_velocity);
    for (int k = 0; k < a.jacobian.count; ++k) out(a.offset + a.jacobian.index[k]) += a.jacobian.column.col(k).dot(force);
    for (int k = 0; k < b.jacobian.count; ++k) out(b.offset + b.jacobian.index[k]) -= b.jacobian.column.col(k).dot(force);
  }
}

// A lumped World's A is rebuilt from this whenever a body with a spring turns: P J_j is formed once
// per column, not once per entry (the same products, so the same K to the bit).
void Springs::stiffness(const Vector& q, Matrix& K) const {
  K.setZero(world_.velocity_size, world_.velocity_size);
  if (empty()) return;
  const Evaluation& e = at(q);
  for (std::size_t i = 0; i < world_.springs.size(); ++i) {
    const End &a = e.ends[2 * i], &b = e.ends[2 * i + 1];
    const Entries entries = entries_of(a.jacobian, a.offset, b.jacobian, b.offset);
    std::array<Eigen::Vector3d, 18> projected;
    for (int j = 0; j < entries.count; ++j) projected[j] = projectors_[i] * entries.entry[j].column;
    for (const Entry& row : entries)
      for (int j = 0; j < entries.count; ++j)
        K(row.index, entries.entry[j].index) += world_.springs[i].stiffness * row.column.dot(projected[j]);
  }
}

}  // namespace csim
