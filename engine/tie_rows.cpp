#include "engine/tie_rows.h"

namespace csim {

TieRows::TieRows(const World& world) : world_(world) {
  for (const RigidTie& tie : world.ties) {
    const BodyInstance& ring = world.bodies[tie.elastic_body];
    const BodyInstance& hub = world.bodies[tie.rigid_body];
    const Body& nodes = *ring.body;
    const Eigen::Isometry3d reference = hub.body->pose(hub.reference_position);
    for (int node : tie.nodes) {
      const Eigen::Vector3d X = nodes.node_reference(node);
      for (int c = 0; c < nodes.node_components(); ++c) {
        const int free = nodes.node_velocity_index(node, c);
        if (free < 0) continue;
        Entry e;
        e.node_velocity = ring.velocity_offset + free;
        e.node_position = ring.position_offset + free;
        e.component = c;
        e.reference = X(c);
        e.hub = tie.rigid_body;
        e.local = reference.inverse() * X;
        entries_.push_back(e);
      }
    }
  }
  rows_.resize(entries_.size());
}

void TieRows::compute_gaps(const Vector& q, Vector& gaps) const {
  gaps.resize(size());
  for (int i = 0; i < size(); ++i) {
    const Entry& e = entries_[i];
    const BodyInstance& hub = world_.bodies[e.hub];
    const Eigen::Vector3d point = hub.body->pose(q.segment(hub.position_offset, hub.body->position_size())) * e.local;
    gaps(i) = e.reference + q(e.node_position) - point(e.component);
  }
}

void TieRows::linearize(const Vector& q) {
  for (int i = 0; i < size(); ++i) {
    const Entry& e = entries_[i];
    const BodyInstance& hub = world_.bodies[e.hub];
    const auto q_hub = q.segment(hub.position_offset, hub.body->position_size());
    SparseRow& row = rows_[i];
    row.clear();
    row.add(e.node_velocity, 1.0);
    const PointJacobian J = hub.body->point_jacobian(q_hub, e.local);
    for (int k = 0; k < J.count; ++k)
      if (J.column(e.component, k) != 0.0) row.add(hub.velocity_offset + J.index[k], -J.column(e.component, k));
  }
}

}  // namespace csim
