#include "engine/contact_stage/contact_detector.h"

#include <cmath>
#include <limits>
#include <optional>

namespace csim {

namespace {

// No velocity component twice in J (a rigid body's Jacobian: components 0, 1, 2, …).
bool ascending(const PointJacobian& J) {
  for (int j = 1; j < J.count; ++j)
    if (J.index[j] <= J.index[j - 1]) return false;
  return true;
}

// The distinct case of contact_rows for D rows: a column of J at a time into every row, the rows'
// common entry count kept in a local (a store through a row's index array may alias its count).
template <int D>
void append_columns(int offset, const PointJacobian& J, double sign, const Eigen::Vector3d* const* axes,
                    SparseRow* rows) {
  int n = rows[0].count;
  for (int j = 0; j < J.count; ++j, ++n) {
    const int index = offset + J.index[j];
    for (int k = 0; k < D; ++k) {
      rows[k].index[n] = index;
      rows[k].value[n] = sign * axes[k]->dot(J.column.col(j));
    }
  }
  for (int k = 0; k < D; ++k) rows[k].count = n;
}

// One side's projected Jacobian into a contact's D rows (sign: −1 on side A). Two distinct bodies own
// disjoint components, so that a side whose components ascend appends its entries without
// SparseRow::add's search; the rows' common count and the side's data are kept in locals (a store
// through a row's arrays may alias them, and they would be read again for every entry).
template <int D>
void append_projections(int offset, const ProjectedJacobian& P, double sign, SparseRow* rows) {
  const int count = P.count;
  bool ascending = true;
  if (!P.ascending)
    for (int j = 1; j < count; ++j) ascending = ascending && P.index[j] > P.index[j - 1];
  if (!ascending) {  // a component named twice: summed by SparseRow::add
    for (int k = 0; k < D; ++k)
      for (int j = 0; j < count; ++j) rows[k].add(offset + P.index[j], sign * P.value(k, j));
    return;
  }
  const int first = rows[0].count;
  for (int j = 0; j < count; ++j) {
    const int index = offset + P.index[j];
    const Eigen::Matrix<double, D, 1> column = sign * P.value.template block<D, 1>(0, j);
    for (int k = 0; k < D; ++k) {
      rows[k].index[first + j] = index;
      rows[k].value[first + j] = column(k);
    }
  }
  for (int k = 0; k < D; ++k) rows[k].count = first + count;
}

}  // namespace

void contact_rows(const World& world, int body_a, const PointJacobian& point_a, int body_b,
                  const PointJacobian& point_b, const ContactPoint& c, int dimension, SparseRow* rows) {
  const Eigen::Vector3d* axes[3] = {&c.normal, &c.t1, &c.t2};
  for (int k = 0; k < dimension; ++k) rows[k].clear();
  const int ids[2] = {body_a, body_b};
  const PointJacobian* jacobians[2] = {&point_a, &point_b};
  // Two bodies own disjoint velocity components: when neither side names one twice, no entry is met
  // twice, and each row takes its entries in SparseRow::add's order without its search (a column of J
  // at a time, all rows together).
  const bool distinct = body_a != body_b && ascending(point_a) && ascending(point_b);
  for (int side = 0; side < 2; ++side) {
    const BodyInstance& b = world.bodies[ids[side]];
    const PointJacobian& J = *jacobians[side];
    const double sign = side == 0 ? -1.0 : 1.0;
    if (distinct) {
      if (dimension == 2) append_columns<2>(b.velocity_offset, J, sign, axes, rows);
      else append_columns<3>(b.velocity_offset, J, sign, axes, rows);
      continue;
    }
    for (int k = 0; k < dimension; ++k)
      for (int j = 0; j < J.count; ++j)
        rows[k].add(b.velocity_offset + J.index[j], sign * axes[k]->dot(J.column.col(j)));
  }
}

ContactDetector::ContactDetector(const World& world)
    : world_(world), dimension_(world.dimension == 2 ? 2 : 3), laws_(world) {
  // Collision objects only for bodies that some contact law's side holds: a scene without contact
  // builds no collision world at all, and a body in no law touches nothing.
  if (world.contact_laws.empty()) return;
  const int nb = static_cast<int>(world.bodies.size());
  collision_ = std::make_unique<CollisionWorld>(world.dimension == 2);
  for (int i = 0; i < nb; ++i) {
    if (!laws_.in_some_law(i)) continue;
    const BodyInstance& b = world.bodies[i];
    const bool elastic = b.body->elastic();
    // The laws whose sides hold an elastic body (few bodies, each a scan of the laws).
    std::vector<int> laws_of_body;
    bool smoothed = false;
    if (elastic)
      for (std::size_t l = 0; l < world.contact_laws.size(); ++l) {
        const ContactLaw& law = world.contact_laws[l];
        const bool on_a = law.body_a == i || (law.group_a >= 0 && law.group_a == b.group);
        const bool on_b = law.body_b == i || (law.group_b >= 0 && law.group_b == b.group);
        if (!on_a && !on_b) continue;
        laws_of_body.push_back(static_cast<int>(l));
        smoothed |= law.features == SurfaceFeatures::smoothed;
      }
    if (const std::optional<ContactSurface> surface = elastic ? b.body->contact_surface(smoothed) : std::nullopt) {
      // A deformable body touches through its surface (node-to-surface against rigid shapes), with the
      // features of the law that governs each pair (nodes unless set).
      const int object = collision_->add_deformable_surface(i, surface->reference_nodes, surface->geometry);
      for (int l : laws_of_body) {
        const ContactLaw& law = world.contact_laws[l];
        if (law.features == SurfaceFeatures::nodes) continue;
        for (int side = 0; side < 2; ++side) {
          const bool on_side = side == 0 ? law.body_a == i || (law.group_a >= 0 && law.group_a == b.group)
                                         : law.body_b == i || (law.group_b >= 0 && law.group_b == b.group);
          if (!on_side) continue;
          for (int other : side == 0 ? side_bodies(world, law.body_b, law.group_b) : side_bodies(world, law.body_a, law.group_a))
            if (other != i && laws_.law(i, other) == l) collision_->set_surface_features(object, other, law.features);
        }
      }
      object_body_.resize(object + 1);
      object_shape_.resize(object + 1);
      node_positions_.resize(object + 1);
      object_body_[object] = i;
      object_shape_[object] = -1;
      shape_at_origin_.resize(object + 1);
      continue;
    }
    for (std::size_t s = 0; s < b.shapes.size(); ++s) {
      const int object = collision_->add_object(i, b.shapes[s].shape, b.body->fixed());
      object_body_.resize(object + 1);
      object_shape_.resize(object + 1);
      object_body_[object] = i;
      object_shape_[object] = static_cast<int>(s);
      shape_at_origin_.resize(object + 1);
      shape_at_origin_[object] = b.shapes[s].local_pose.translation().isZero(0.0);
      collision_->set_pose(object, b.body->pose(b.initial_position) * b.shapes[s].local_pose);
    }
  }
  // Bodies that share no law never reach the narrow phase (the filter reads laws_: the detector, which
  // owns collision_, is neither copied nor moved).
  collision_->set_body_filter([this](int a, int b) { return touching_law(a, b) >= 0; });
}

ContactDetector::~ContactDetector() = default;

PointJacobian ContactDetector::side_jacobian(const Vector& q, int object, const ContactPoint& c,
                                             const Eigen::Vector3d& world_point) const {
  const BodyInstance& b = world_.bodies[object_body_[object]];
  if (b.body->fixed()) return {};
  if (object_shape_[object] < 0) return b.body->surface_point_jacobian(b.positions(q), c.surface);
  return b.body->world_point_jacobian(b.positions(q), world_point);
}

void ContactDetector::move_contact(const Vector& q0, const Vector& dq, ContactPoint& c) const {
  Eigen::Vector3d motion[2];
  const int objects[2] = {c.key.object_a, c.key.object_b};
  const Eigen::Vector3d points[2] = {c.point_a, c.point_b};
  for (int side = 0; side < 2; ++side) {
    const PointJacobian J = side_jacobian(q0, objects[side], c, points[side]);
    const int offset = world_.bodies[object_body_[objects[side]]].velocity_offset;
    motion[side].setZero();
    for (int k = 0; k < J.count; ++k) motion[side] += J.column.col(k) * dq(offset + J.index[k]);
  }
  c.point_a += motion[0];
  c.point_b += motion[1];
  c.gap += c.normal.dot(motion[1] - motion[0]);
}

void ContactDetector::shape_contact_rows(const Vector& q, int body_a, int body_b, const ContactPoint& c,
                                         SparseRow* rows) const {
  const int d = dimension_;
  const Eigen::Vector3d* axes[3] = {&c.normal, &c.t1, &c.t2};
  for (int k = 0; k < d; ++k) rows[k].clear();
  const int ids[2] = {body_a, body_b};
  const Eigen::Vector3d* points[2] = {&c.point_a, &c.point_b};
  const Eigen::Vector3d* arms[2] = {&c.arm_a, &c.arm_b};
  const bool has_arm[2] = {c.has_arm_a() && shape_at_origin_[c.key.object_a],
                           c.has_arm_b() && shape_at_origin_[c.key.object_b]};
  ProjectedJacobian P;
  for (int side = 0; side < 2; ++side) {
    const BodyInstance& b = world_.bodies[ids[side]];
    if (b.body->fixed()) continue;
    // A material point's arm from its shape's origin is the body's where the two origins are one.
    if (has_arm[side]) b.body->project_lever_arm_jacobian(b.positions(q), *arms[side], axes, d, P);
    else b.body->project_world_point_jacobian(b.positions(q), *points[side], axes, d, P);
    const double sign = side == 0 ? -1.0 : 1.0;
    if (d == 2) append_projections<2>(b.velocity_offset, P, sign, rows);
    else append_projections<3>(b.velocity_offset, P, sign, rows);
  }
}

double ContactDetector::travel_bound(const Vector& v, double h) const {
  double speed = 0.0;
  for (const BodyInstance& b : world_.bodies)
    if (!b.body->fixed()) speed = std::max(speed, b.point_speed_bound(v, world_.dimension));
  return speed * h;
}

void ContactDetector::detect(const Vector& q, double margin, std::vector<ActiveContact>& contacts,
                             std::vector<SparseRow>& rows) {
  contacts.clear();
  rows.clear();
  if (!collision_) return;
  bool moving = false;  // some object of an awake moving body: otherwise no pair is examined (set_asleep)
  for (std::size_t o = 0; o < object_body_.size(); ++o) {
    if (resting(object_body_[o])) continue;
    const BodyInstance& b = world_.bodies[object_body_[o]];
    moving = true;
    if (object_shape_[o] < 0) {
      b.body->surface_node_positions(b.positions(q), collision_->surface_nodes(static_cast<int>(o)), node_positions_[o]);
      collision_->set_node_positions(static_cast<int>(o), node_positions_[o]);
      continue;
    }
    collision_->set_pose(static_cast<int>(o),
                         b.body->pose(b.positions(q)) * b.shapes[object_shape_[o]].local_pose);
  }
  if (!moving && asleep_) return;
  collision_->update(margin);
  collision_->find_contacts(points_);

  const int d = dimension_;
  rows.resize(d * points_.size());
  for (ContactPoint& point : points_) {
    const int body_a = object_body_[point.key.object_a], body_b = object_body_[point.key.object_b];
    const int law_index = body_a == body_b ? -1 : touching_law(body_a, body_b);
    if (law_index < 0) continue;
    const ContactLaw& law = world_.contact_laws[law_index];
    if (!law.isotropic()) complete_frame(point, world_.dimension == 2, law.friction_direction);
    const int i = static_cast<int>(contacts.size());
    if (body_a != body_b && object_shape_[point.key.object_a] >= 0 && object_shape_[point.key.object_b] >= 0)
      shape_contact_rows(q, body_a, body_b, point, &rows[d * i]);
    else
      contact_rows(world_, body_a, side_jacobian(q, point.key.object_a, point, point.point_a), body_b,
                   side_jacobian(q, point.key.object_b, point, point.point_b), point, d, &rows[d * i]);
    ActiveContact& c = contacts.emplace_back();
    c.point = point;
    c.law = law_index;
    c.body_a = body_a;
    c.body_b = body_b;
  }
}

}  // namespace csim
