#include "engine/reduced_coordinates.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace csim {

namespace {

// A prescription that holds its component at the reference value for all time.
bool held_at_reference(const PrescribedComponent& p) {
  if (p.value.table.empty()) return false;  // a multiplier, not a value
  return std::all_of(p.value.table.begin(), p.value.table.end(), [](const auto& point) { return point.second == 0.0; });
}

// Writes the entries' values into T when they fill its pattern one to one (every iterate of a run but
// those where the unknowns or a hub column's nonzeros change): the matrix setFromTriplets would make,
// without its assembly. False, with T's values partly written, when they do not.
bool write_in_pattern(const Triplets& entries, SparseRowMatrix& T) {
  if (!T.isCompressed() || T.nonZeros() != static_cast<Eigen::Index>(entries.size())) return false;
  std::vector<char> written(entries.size(), 0);
  for (const Eigen::Triplet<double>& entry : entries) {
    const int* first = T.innerIndexPtr() + T.outerIndexPtr()[entry.row()];
    const int* last = T.innerIndexPtr() + T.outerIndexPtr()[entry.row() + 1];
    const int* found = std::find(first, last, entry.col());
    if (found == last) return false;
    const std::ptrdiff_t slot = found - T.innerIndexPtr();
    if (written[slot]) return false;  // a repeated entry, which setFromTriplets would sum
    written[slot] = 1;
    T.valuePtr()[slot] = entry.value();
  }
  return true;
}

}  // namespace

ReducedCoordinates::ReducedCoordinates(const World& world, double t) : world_(&world) {
  const int n = world.velocity_size;
  unknown_of_.assign(n, -1);
  prescription_of_.assign(n, -1);
  floating_of_.assign(n, -1);
  position_of_.assign(n, -1);
  for (std::size_t b = 0; b < world.bodies.size(); ++b) {
    const BodyInstance& body = world.bodies[b];
    bool incremental = false;
    for (int c = 0; c < body.body->velocity_size(); ++c) {
      const int coordinate = body.body->coordinate_of(c);
      if (coordinate >= 0) position_of_[body.velocity_offset + c] = body.position_offset + coordinate;
      else incremental = true;
    }
    if (incremental) incremental_bodies_.push_back(static_cast<int>(b));
  }
  for (std::size_t p = 0; p < world.prescribed.size(); ++p) {
    const PrescribedComponent& c = world.prescribed[p];
    if (!c.active(t)) continue;
    const int i = world.bodies[c.body].velocity_offset + c.component;
    if (prescription_of_[i] >= 0)
      throw std::invalid_argument("component " + std::to_string(c.component) + " of body '" +
                                  world.bodies[c.body].name + "' is prescribed twice");
    prescription_of_[i] = static_cast<int>(p);
  }
  floating_body_of_.assign(world.bodies.size(), -1);
  std::vector<bool> tied_node;
  for (const RigidTie& tie : world.ties) {
    const BodyInstance& ring = world.bodies[tie.elastic_body];
    const BodyInstance& rigid = world.bodies[tie.rigid_body];
    const Body& tied = *ring.body;  // its nodes ride in the hub's frame
    if (tied.node_count() == 0 || rigid.body->rotation_axes().empty())
      throw std::invalid_argument("tie '" + tie.name + "' must join an elastic body to a rigid body");
    if (floating_of_[ring.velocity_offset] >= 0) throw std::invalid_argument("body '" + ring.name + "' has two ties");
    int hub_index = 0;
    while (hub_index < static_cast<int>(hubs_.size()) && hubs_[hub_index].body != tie.rigid_body) ++hub_index;
    if (hub_index == static_cast<int>(hubs_.size())) {
      Hub hub;
      hub.body = tie.rigid_body;
      const Eigen::Isometry3d reference = rigid.body->pose(rigid.reference_position);
      hub.rotation_ref = reference.linear();
      hub.centre_ref = reference.translation();
      hub.axes = rigid.body->rotation_axes();
      hubs_.push_back(hub);
    }
    const Hub& hub = hubs_[hub_index];
    const int nodes = tied.node_count(), dimension = tied.node_components();
    for (int c = 0; c < dimension; ++c)
      for (int node = 0; node < nodes; ++node)
        if (tied.node_velocity_index(node, c) < 0) {
          check_fixed_component(hub, c, ring.name);
          break;
        }
    tied_node.assign(nodes, false);
    for (int node : tie.nodes) tied_node[node] = true;
    floating_body_of_[tie.elastic_body] = static_cast<int>(floating_bodies_.size());
    floating_bodies_.emplace_back(static_cast<int>(floating_.size()), static_cast<int>(floating_.size()) + nodes);
    for (int node = 0; node < nodes; ++node) {
      Floating f;
      f.hub = hub_index;
      f.arm = tied.node_reference(node) - hub.centre_ref;
      for (int c = 0; c < dimension; ++c) {
        const int free = tied.node_velocity_index(node, c);
        if (free < 0) continue;
        f.dof[c] = ring.velocity_offset + free;
        f.position[c] = ring.position_offset + free;
        f.unknown[c] = tied_node[node] ? -1 : -2;  // numbered below
        floating_of_[f.dof[c]] = static_cast<int>(floating_.size());
      }
      floating_.push_back(f);
    }
  }
  // The unknowns in velocity order, a floating node's at its components.
  for (int i = 0; i < n; ++i) {
    if (prescription_of_[i] >= 0) continue;
    if (floating_of_[i] < 0) {
      unknown_of_[i] = unknown_count_++;
      continue;
    }
    Floating& f = floating_[floating_of_[i]];
    for (int c = 0; c < 3; ++c)
      if (f.dof[c] == i && f.unknown[c] == -2) f.unknown[c] = unknown_count_++;
  }
  selected_ = unknown_of_;
  for (const Floating& f : floating_)
    for (int c = 0; c < 3; ++c)
      if (f.dof[c] >= 0) selected_[f.dof[c]] = f.unknown[c];
  identity_ = unknown_count_ == n && floating_.empty();
  for (const Hub& hub : hubs_) {
    const BodyInstance& rigid = world.bodies[hub.body];
    for (int c = 0; c < rigid.body->velocity_size(); ++c) {
      const int u = unknown_of_[rigid.velocity_offset + c];
      if (u >= 0 && std::find(hub_unknowns_.begin(), hub_unknowns_.end(), u) == hub_unknowns_.end())
        hub_unknowns_.push_back(u);
    }
  }
}

// A fixed component c of a tied body stays put only if the frame never moves it: the hub's
// translation along c and its rotations about the axes that are not along c held at 0.
void ReducedCoordinates::check_fixed_component(const Hub& hub, int c, const std::string& body_name) const {
  const BodyInstance& rigid = world_->bodies[hub.body];
  auto held = [&](int component) {
    const int p = prescription_of_[rigid.velocity_offset + component];
    return p >= 0 && held_at_reference(world_->prescribed[p]);
  };
  bool ok = held(c);
  for (const auto& [component, axis] : hub.axes)
    if ((hub.rotation_ref * axis).cross(Eigen::Vector3d::Unit(c)).norm() > 1e-12) ok = ok && held(component);
  if (!ok) {
    const char* names = "xyz";
    throw std::invalid_argument("body '" + body_name + "' has fixed " + names[c] + " components but rides on '" +
                                rigid.name + "', which may move them: prescribe its " + names[c] +
                                " and its rotations about the other axes at 0");
  }
}

Eigen::Isometry3d ReducedCoordinates::hub_pose(const Hub& hub, const Vector& q) const {
  const BodyInstance& rigid = world_->bodies[hub.body];
  return rigid.body->pose(q.segment(rigid.position_offset, rigid.body->position_size()));
}

std::vector<Eigen::Isometry3d> ReducedCoordinates::hub_poses(const Vector& q) const {
  std::vector<Eigen::Isometry3d> poses(hubs_.size());
  for (std::size_t h = 0; h < hubs_.size(); ++h) poses[h] = hub_pose(hubs_[h], q);
  return poses;
}

// x = X + u = x_B,ref + a + u (u = 0 on fixed components).
Eigen::Vector3d ReducedCoordinates::node_position(const Floating& node, const Vector& q) const {
  Eigen::Vector3d x = hubs_[node.hub].centre_ref + node.arm;
  for (int c = 0; c < 3; ++c)
    if (node.position[c] >= 0) x(c) += q(node.position[c]);
  return x;
}

Eigen::Vector3d ReducedCoordinates::node_force(const Floating& node, const Vector& f) const {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  for (int c = 0; c < 3; ++c)
    if (node.dof[c] >= 0) force(c) = f(node.dof[c]);
  return force;
}

void ReducedCoordinates::gather(const Vector& q, double t, Vector& z) {
  base_ = q;
  base_time_ = t;
  z.resize(unknown_count_);
  for (int i = 0; i < static_cast<int>(unknown_of_.size()); ++i)
    if (unknown_of_[i] >= 0) z(unknown_of_[i]) = position_of_[i] >= 0 ? q(position_of_[i]) : 0.0;  // rotations: from q
  const std::vector<Eigen::Isometry3d> poses = hub_poses(q);
  for (const Floating& f : floating_) {
    const Eigen::Isometry3d& pose = poses[f.hub];
    const Eigen::Matrix3d relative = relative_rotation(hubs_[f.hub], pose);
    const Eigen::Vector3d w = relative.transpose() * (node_position(f, q) - pose.translation()) - f.arm;
    for (int c = 0; c < 3; ++c)
      if (f.unknown[c] >= 0) z(f.unknown[c]) = w(c);
  }
}

void ReducedCoordinates::expand(const Vector& z, double t, Vector& q) const {
  const World& world = *world_;
  if (!incremental_bodies_.empty() && base_.size() != world.position_size)
    throw std::logic_error("ReducedCoordinates::expand before gather");
  q.resize(world.position_size);
  // The rotations of 3D rigid bodies from their base, then the components that are coordinates.
  for (int b : incremental_bodies_) {
    const BodyInstance& body = world.bodies[b];
    Vector increment = Vector::Zero(body.body->velocity_size());
    for (int c = 0; c < increment.size(); ++c) {
      const int i = body.velocity_offset + c;
      if (position_of_[i] >= 0) continue;  // set below, from z or the prescription
      if (unknown_of_[i] >= 0) increment(c) = z(unknown_of_[i]);
      else if (prescription_of_[i] >= 0) {
        const TimeFunction& angle = world.prescribed[prescription_of_[i]].value;
        increment(c) = angle(t) - angle(base_time_);
      }
    }
    const int offset = body.position_offset, size = body.body->position_size();
    body.body->integrate_position(base_.segment(offset, size), increment, 1.0, q.segment(offset, size));
  }
  for (int i = 0; i < static_cast<int>(unknown_of_.size()); ++i) {
    if (position_of_[i] < 0) continue;
    if (unknown_of_[i] >= 0) {
      q(position_of_[i]) = z(unknown_of_[i]);
    } else if (prescription_of_[i] >= 0) {
      const PrescribedComponent& c = world.prescribed[prescription_of_[i]];
      const BodyInstance& body = world.bodies[c.body];
      q(position_of_[i]) = body.reference_position(position_of_[i] - body.position_offset) + c.value(t);
    }
  }
  // The floating nodes last: their rigid body's coordinates are set by now.
  const std::vector<Eigen::Isometry3d> poses = hub_poses(q);
  const std::vector<Eigen::Matrix3d> relative_of = relative_rotations(poses);
  for (const Floating& f : floating_) {
    const Hub& hub = hubs_[f.hub];
    const Eigen::Isometry3d& pose = poses[f.hub];
    Eigen::Vector3d w = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c)
      if (f.unknown[c] >= 0) w(c) = z(f.unknown[c]);
    const Eigen::Vector3d u = pose.translation() + relative_of[f.hub] * (f.arm + w) - hub.centre_ref - f.arm;
    for (int c = 0; c < 3; ++c)
      if (f.position[c] >= 0) q(f.position[c]) = u(c);
  }
}

Eigen::Matrix3d ReducedCoordinates::relative_rotation(const Hub& hub, const Eigen::Isometry3d& pose) const {
  return pose.linear() * hub.rotation_ref.transpose();
}

std::vector<Eigen::Matrix3d> ReducedCoordinates::relative_rotations(const std::vector<Eigen::Isometry3d>& poses) const {
  std::vector<Eigen::Matrix3d> relative(hubs_.size());
  for (std::size_t h = 0; h < hubs_.size(); ++h) relative[h] = relative_rotation(hubs_[h], poses[h]);
  return relative;
}

PointJacobian ReducedCoordinates::hub_columns(const Floating& node, const Vector& q,
                                              const Eigen::Isometry3d& inverse_pose) const {
  const BodyInstance& rigid = world_->bodies[hubs_[node.hub].body];
  return rigid.body->point_jacobian(q.segment(rigid.position_offset, rigid.body->position_size()),
                                    inverse_pose * node_position(node, q));
}

std::vector<Eigen::Isometry3d> ReducedCoordinates::inverses(const std::vector<Eigen::Isometry3d>& poses) {
  std::vector<Eigen::Isometry3d> inverse(poses.size());
  for (std::size_t h = 0; h < poses.size(); ++h) inverse[h] = poses[h].inverse();
  return inverse;
}

void ReducedCoordinates::prescribed_forces(const Vector& q, const Vector& f, Vector& forces) const {
  const int n = static_cast<int>(unknown_of_.size());
  forces.setZero(n);
  for (int i = 0; i < n; ++i)
    if (prescription_of_[i] >= 0) forces(i) = f(i);
  const std::vector<Eigen::Isometry3d> inverse = inverses(hub_poses(q));
  for (const Floating& node : floating_) {
    const Hub& hub = hubs_[node.hub];
    const BodyInstance& rigid = world_->bodies[hub.body];
    const PointJacobian J = hub_columns(node, q, inverse[node.hub]);
    const Eigen::Vector3d force = node_force(node, f);
    for (int k = 0; k < J.count; ++k) {
      const int i = rigid.velocity_offset + J.index[k];
      if (prescription_of_[i] >= 0) forces(i) += force.dot(J.column.col(k));
    }
  }
}

void ReducedCoordinates::tangent(const Vector& q, SparseRowMatrix& T) const {
  const int n = static_cast<int>(unknown_of_.size());
  Triplets entries;
  entries.reserve(n + 9 * floating_.size());
  for (int i = 0; i < n; ++i)
    if (unknown_of_[i] >= 0 && floating_of_[i] < 0) entries.emplace_back(i, unknown_of_[i], 1.0);
  const std::vector<Eigen::Isometry3d> poses = hub_poses(q), inverse = inverses(poses);
  const std::vector<Eigen::Matrix3d> relative_of = relative_rotations(poses);
  for (const Floating& f : floating_) {
    const Hub& hub = hubs_[f.hub];
    const BodyInstance& rigid = world_->bodies[hub.body];
    const Eigen::Matrix3d& relative = relative_of[f.hub];
    const PointJacobian J = hub_columns(f, q, inverse[f.hub]);
    for (int c = 0; c < 3; ++c) {
      if (f.dof[c] < 0) continue;
      for (int k = 0; k < J.count; ++k) {
        const int u = unknown_of_[rigid.velocity_offset + J.index[k]];
        if (u >= 0 && J.column(c, k) != 0.0) entries.emplace_back(f.dof[c], u, J.column(c, k));
      }
      for (int k = 0; k < 3; ++k)
        if (f.unknown[k] >= 0) entries.emplace_back(f.dof[c], f.unknown[k], relative(c, k));
    }
  }
  if (T.rows() == n && T.cols() == unknown_count_ && write_in_pattern(entries, T)) return;
  T.resize(n, unknown_count_);
  T.setFromTriplets(entries.begin(), entries.end());
}

void ReducedCoordinates::frame_positions(const Vector& q, int body, Vector& positions) const {
  const BodyInstance& b = world_->bodies[body];
  positions.setZero(b.body->position_size());
  const auto [first, last] = floating_bodies_[floating_body_of_[body]];
  const Hub& hub = hubs_[floating_[first].hub];
  const Eigen::Isometry3d pose = hub_pose(hub, q);
  const Eigen::Matrix3d relative = relative_rotation(hub, pose);
  for (int a = first; a < last; ++a) {
    const Floating& node = floating_[a];
    const Eigen::Vector3d w = relative.transpose() * (node_position(node, q) - pose.translation()) - node.arm;
    for (int c = 0; c < 3; ++c)  // a tied node stays at X: w = 0, not its round-off
      if (node.unknown[c] >= 0) positions(node.position[c] - b.position_offset) = w(c);
  }
}

void ReducedCoordinates::add_turned_to_world(const Vector& q, int body, const Vector& f_frame, VectorRef f) const {
  const BodyInstance& b = world_->bodies[body];
  const auto [first, last] = floating_bodies_[floating_body_of_[body]];
  const Hub& hub = hubs_[floating_[first].hub];
  const Eigen::Matrix3d relative = relative_rotation(hub, hub_pose(hub, q));
  for (int a = first; a < last; ++a) {
    const Floating& node = floating_[a];
    Eigen::Vector3d local = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c)
      if (node.dof[c] >= 0) local(c) = f_frame(node.dof[c] - b.velocity_offset);
    const Eigen::Vector3d turned = relative * local;  // no fixed component gains a part (check_fixed_component)
    for (int c = 0; c < 3; ++c)
      if (node.dof[c] >= 0) f(node.dof[c] - b.velocity_offset) += turned(c);
  }
}

// K'(a c', j) = Σ_c R_rel(c, c') K(a c, j) on a floating node's rows, and the same on its columns.
void ReducedCoordinates::add_turned_to_frame(const Vector& q, const Triplets& K, std::size_t from,
                                             Triplets& entries) const {
  struct Side {
    int count = 1;
    std::array<int, 3> index{};
    std::array<double, 3> weight{1.0, 0.0, 0.0};
  };
  if (from == K.size()) return;
  const std::vector<Eigen::Matrix3d> relative = relative_rotations(hub_poses(q));
  auto side = [&](int i) {
    Side s;
    s.index[0] = i;
    if (floating_of_[i] < 0) return s;
    const Floating& node = floating_[floating_of_[i]];
    const Eigen::Matrix3d& R = relative[node.hub];
    int c = 0;
    while (node.dof[c] != i) ++c;
    s.count = 0;
    for (int k = 0; k < 3; ++k)
      if (node.dof[k] >= 0) {
        s.index[s.count] = node.dof[k];
        s.weight[s.count++] = R(c, k);
      }
    return s;
  };
  for (std::size_t t = from; t < K.size(); ++t) {
    const Side row = side(K[t].row()), column = side(K[t].col());
    for (int a = 0; a < row.count; ++a)
      for (int b = 0; b < column.count; ++b)
        entries.emplace_back(row.index[a], column.index[b], row.weight[a] * K[t].value() * column.weight[b]);
  }
}

void ReducedCoordinates::hub_frame_columns(const Vector& q, Matrix& C) const {
  C.setZero(static_cast<Eigen::Index>(unknown_of_.size()), static_cast<Eigen::Index>(hub_unknowns_.size()));
  const std::vector<Eigen::Isometry3d> poses = hub_poses(q), inverse = inverses(poses);
  const std::vector<Eigen::Matrix3d> relative_of = relative_rotations(poses);
  for (const Floating& node : floating_) {
    const Hub& hub = hubs_[node.hub];
    const BodyInstance& rigid = world_->bodies[hub.body];
    const Eigen::Matrix3d& relative = relative_of[node.hub];
    const PointJacobian J = hub_columns(node, q, inverse[node.hub]);
    for (int k = 0; k < J.count; ++k) {
      const int u = unknown_of_[rigid.velocity_offset + J.index[k]];
      if (u < 0) continue;
      const auto column = std::find(hub_unknowns_.begin(), hub_unknowns_.end(), u) - hub_unknowns_.begin();
      const Eigen::Vector3d turned = relative.transpose() * J.column.col(k);
      for (int c = 0; c < 3; ++c)
        if (node.dof[c] >= 0) C(node.dof[c], column) = turned(c);
    }
  }
}

void ReducedCoordinates::reduce_stiffness(const Vector& q, const Vector& f, const Triplets& K, std::size_t world_from,
                                          SparseMatrix& K_z) {
  assembly_.begin();
  if (identity_) {
    assembly_.add(K);
    assembly_.finish(unknown_count_, unknown_count_, K_z);
    return;
  }
  const int n = static_cast<int>(unknown_of_.size()), hubs = static_cast<int>(hub_unknowns_.size());
  turned_.clear();
  add_turned_to_frame(q, K, world_from, turned_);
  if (hubs > 0) {
    hub_frame_columns(q, C_);
    KC_.setZero(n, hubs);
    CK_.setZero(n, hubs);
    reaches_hub_row_.assign(n, 0);
    reaches_hub_column_.assign(n, 0);
  }
  // Sᵀ K' S as it is; K' C and Cᵀ K' (kept apart: K' need not be symmetric).
  auto hub_part = [&](int i, int j, double value) {
    if (floating_of_[j] >= 0) {
      for (int h = 0; h < hubs; ++h) KC_(i, h) += value * C_(j, h);
      reaches_hub_row_[i] = 1;
    }
    if (floating_of_[i] >= 0) {
      for (int h = 0; h < hubs; ++h) CK_(j, h) += value * C_(i, h);
      reaches_hub_column_[j] = 1;
    }
  };
  auto visit = [&](const Eigen::Triplet<double>& t) {
    const int i = t.row(), j = t.col();
    if (selected_[i] >= 0 && selected_[j] >= 0) assembly_.add(selected_[i], selected_[j], t.value());
    if (hubs > 0) hub_part(i, j, t.value());
  };
  // The frame entries, K's head: at the positions of the last iterate, summed straight into K_z's slots.
  const bool planned = world_from > 0 && same_frame_positions(K, world_from);
  if (planned) {
    frame_sums_.assign(assembly_.nonzeros(), 0.0);
    if (hubs == 1) {  // hub_part with its one column as plain arrays (every tied ring): the same sums
      const double* C = C_.data();
      double* KC = KC_.data();
      double* CK = CK_.data();
      for (std::size_t t = 0; t < world_from; ++t) {
        const int i = K[t].row(), j = K[t].col();
        const double value = K[t].value();
        if (frame_slot_[t] >= 0) frame_sums_[frame_slot_[t]] += value;
        if (floating_of_[j] >= 0) {
          KC[i] += value * C[j];
          reaches_hub_row_[i] = 1;
        }
        if (floating_of_[i] >= 0) {
          CK[j] += value * C[i];
          reaches_hub_column_[j] = 1;
        }
      }
    } else {
      for (std::size_t t = 0; t < world_from; ++t) {
        const double value = K[t].value();
        if (frame_slot_[t] >= 0) frame_sums_[frame_slot_[t]] += value;
        if (hubs > 0) hub_part(K[t].row(), K[t].col(), value);
      }
    }
    assembly_.resume(frame_entries_, frame_sums_);
  } else {
    for (std::size_t t = 0; t < world_from; ++t) visit(K[t]);
  }
  for (const auto& t : turned_) visit(t);
  // Sᵀ K' C, Cᵀ K' S and Cᵀ K' C; every entry that K's pattern reaches, zero or not, so that K_z's
  // pattern stays that of K (sparse_ldlt.h analyses it again when it changes).
  for (int i = 0; i < n && hubs > 0; ++i) {
    if (selected_[i] < 0) continue;
    for (int h = 0; h < hubs; ++h) {
      if (reaches_hub_row_[i]) assembly_.add(selected_[i], hub_unknowns_[h], KC_(i, h));
      if (reaches_hub_column_[i]) assembly_.add(hub_unknowns_[h], selected_[i], CK_(i, h));
    }
  }
  if (hubs > 0) {
    const Matrix CKC = C_.transpose() * KC_;
    for (int h = 0; h < hubs; ++h)
      for (int l = 0; l < hubs; ++l) assembly_.add(hub_unknowns_[h], hub_unknowns_[l], CKC(h, l));
  }
  geometric_.clear();
  add_geometric_stiffness(q, f, geometric_);
  assembly_.add(geometric_);
  if (assembly_.finish(unknown_count_, unknown_count_, K_z) || !planned) plan_frame(K, world_from);
}

bool ReducedCoordinates::same_frame_positions(const Triplets& K, std::size_t world_from) const {
  if (!frame_planned_ || frame_position_.size() != world_from) return false;
  for (std::size_t t = 0; t < world_from; ++t)
    if (frame_position_[t][0] != K[t].row() || frame_position_[t][1] != K[t].col()) return false;
  return true;
}

// After an assembly that added every frame entry (or built a new pattern): their positions and slots.
void ReducedCoordinates::plan_frame(const Triplets& K, std::size_t world_from) {
  frame_position_.resize(world_from);
  frame_slot_.resize(world_from);
  std::size_t k = 0;  // the entry's place in the assembly's stream
  for (std::size_t t = 0; t < world_from; ++t) {
    const int i = K[t].row(), j = K[t].col();
    frame_position_[t] = {i, j};
    frame_slot_[t] = selected_[i] >= 0 && selected_[j] >= 0 ? assembly_.slot(k++) : -1;
  }
  frame_entries_ = k;
  frame_planned_ = true;
}

bool ReducedCoordinates::geometric_stiffness(const Vector& q, const Vector& f, SparseMatrix& G) const {
  Triplets geometric;
  add_geometric_stiffness(q, f, geometric);
  if (geometric.empty()) return false;
  G.resize(unknown_count_, unknown_count_);
  G.setFromTriplets(geometric.begin(), geometric.end());
  return true;
}

void ReducedCoordinates::add_geometric_stiffness(const Vector& q, const Vector& f, Triplets& geometric) const {
  const std::vector<Eigen::Isometry3d> poses = hub_poses(q);
  for (const Floating& node : floating_) {
    const Hub& hub = hubs_[node.hub];
    const BodyInstance& rigid = world_->bodies[hub.body];
    const Eigen::Isometry3d& pose = poses[node.hub];
    const Eigen::Matrix3d& R = pose.linear();
    const Eigen::Vector3d s = R.transpose() * (node_position(node, q) - pose.translation());  // body-frame arm
    const Eigen::Vector3d force = node_force(node, f);
    if (force.isZero(0.0)) continue;
    for (const auto& [ci, ei] : hub.axes) {
      const int ui = unknown_of_[rigid.velocity_offset + ci];
      if (ui < 0) continue;
      for (const auto& [cj, ej] : hub.axes) {
        const int uj = unknown_of_[rigid.velocity_offset + cj];
        if (uj < 0) continue;
        const Eigen::Vector3d second = 0.5 * (ei.cross(ej.cross(s)) + ej.cross(ei.cross(s)));
        geometric.emplace_back(ui, uj, -force.dot(R * second));
      }
      for (int k = 0; k < 3; ++k) {
        if (node.unknown[k] < 0) continue;
        const double value = -force.dot(R * ei.cross(hub.rotation_ref.transpose().col(k)));
        geometric.emplace_back(ui, node.unknown[k], value);
        geometric.emplace_back(node.unknown[k], ui, value);
      }
    }
  }
}

}  // namespace csim
