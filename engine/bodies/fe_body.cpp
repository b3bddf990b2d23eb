#include "engine/bodies/fe_body.h"

#include "fem/assembly.h"

#include <cmath>

namespace csim {

namespace {

// Keeps the rows and columns of the free dofs: A_ff = Pᵀ A P for the selection P.
SparseMatrix restrict_matrix(const SparseMatrix& full, const std::vector<int>& free_of_dof, int free_count) {
  Triplets kept;
  kept.reserve(full.nonZeros());
  for (int column = 0; column < full.outerSize(); ++column)
    for (SparseMatrix::InnerIterator it(full, column); it; ++it) {
      const int i = free_of_dof[it.row()], j = free_of_dof[it.col()];
      if (i >= 0 && j >= 0) kept.emplace_back(i, j, it.value());
    }
  SparseMatrix restricted(free_count, free_count);
  restricted.setFromTriplets(kept.begin(), kept.end());
  return restricted;
}

// The coupling of the free dofs to the fixed ones, summed over each fixed dof's component (the header's
// fixed_coupling_): free_count × d.
SparseMatrix fixed_coupling(const SparseMatrix& full, const std::vector<int>& free_of_dof, int free_count, int d) {
  Triplets kept;
  for (int column = 0; column < full.outerSize(); ++column)
    for (SparseMatrix::InnerIterator it(full, column); it; ++it) {
      const int i = free_of_dof[it.row()];
      if (i >= 0 && free_of_dof[it.col()] < 0) kept.emplace_back(i, static_cast<int>(it.col()) % d, it.value());
    }
  SparseMatrix coupling(free_count, d);
  coupling.setFromTriplets(kept.begin(), kept.end());
  return coupling;
}

void append_shifted(const SparseMatrix& matrix, int offset, Triplets& out) {
  for (int column = 0; column < matrix.outerSize(); ++column)
    for (SparseMatrix::InnerIterator it(matrix, column); it; ++it)
      out.emplace_back(offset + it.row(), offset + it.col(), it.value());
}

}  // namespace

FeBody::FeBody(Mesh mesh, const ElasticMaterial& material, double thickness, bool lumped_mass,
               const std::vector<std::pair<int, int>>& fixed, double alpha, double beta)
    : mesh_(std::move(mesh)), material_(material), thickness_(thickness), alpha_(alpha), beta_(beta) {
  check_material(material_);
  build(lumped_mass, fixed);
}

namespace {

// E and ν of the linearization at F = I (Lamé λ, μ of hyperelastic.h).
ElasticMaterial linearized(const HyperelasticMaterial& material) {
  check_hyperelastic(material);
  const InitialModuli moduli = initial_moduli(material);
  ElasticMaterial linear;
  linear.young = moduli.mu * (3.0 * moduli.lambda + 2.0 * moduli.mu) / (moduli.lambda + moduli.mu);
  linear.poisson = moduli.lambda / (2.0 * (moduli.lambda + moduli.mu));
  linear.density = material.density;
  return linear;
}

}  // namespace

FeBody::FeBody(Mesh mesh, const FiniteStrainLaw& law, double thickness, bool lumped_mass,
               const std::vector<std::pair<int, int>>& fixed, double alpha, double beta)
    : mesh_(std::move(mesh)), material_(linearized(law.material)), finite_strain_(law), thickness_(thickness),
      alpha_(alpha), beta_(beta) {
  build(lumped_mass, fixed);
}

void FeBody::build(bool lumped_mass, const std::vector<std::pair<int, int>>& fixed) {
  check_mesh(mesh_);
  const int d = mesh_.dofs_per_node();
  std::vector<bool> held(mesh_.dof_count(), false);
  for (const auto& [node, component] : fixed) held[d * node + component] = true;
  free_of_dof_.assign(mesh_.dof_count(), -1);
  for (int dof = 0; dof < mesh_.dof_count(); ++dof)
    if (!held[dof]) free_of_dof_[dof] = free_count_++;

  const FeModel model{mesh_, material_, thickness_};
  const SparseMatrix full_mass = assemble_mass(model, lumped_mass);
  mass_ = restrict_matrix(full_mass, free_of_dof_, free_count_);
  fixed_coupling_ = fixed_coupling(full_mass, free_of_dof_, free_count_, d);
  stiffness_ = restrict_matrix(assemble_stiffness(model), free_of_dof_, free_count_);
  // ρV from the mass of one direction: the sum of the x-x block.
  for (int column = 0; column < full_mass.outerSize(); ++column)
    for (SparseMatrix::InnerIterator it(full_mass, column); it; ++it)
      if (it.row() % d == 0 && it.col() % d == 0) total_mass_ += it.value();

  Eigen::Vector3d low = mesh_.nodes.front(), high = low;
  for (const Eigen::Vector3d& x : mesh_.nodes) {
    low = low.cwiseMin(x);
    high = high.cwiseMax(x);
  }
  size_ = std::max((high - low).norm(), 1e-300);
  for (std::size_t i = 0; i < mesh_.nodes.size(); ++i) node_of_coordinates_.emplace(mesh_.nodes[i], static_cast<int>(i));
  bounding_radius = high.cwiseAbs().cwiseMax(low.cwiseAbs()).norm();
}

void FeBody::add_mass(int offset, Triplets& mass) const { append_shifted(mass_, offset, mass); }

void FeBody::add_stiffness(int offset, Triplets& stiffness) const { append_shifted(stiffness_, offset, stiffness); }

void FeBody::add_damping(int offset, Triplets& damping) const {
  if (alpha_ > 0.0) append_shifted(alpha_ * mass_, offset, damping);
  if (beta_ > 0.0) append_shifted(beta_ * stiffness_, offset, damping);
}

void FeBody::add_internal_force(const ConstVectorRef& q, VectorRef f) const {
  if (!finite_strain_) {
    f -= stiffness_ * q;
    return;
  }
  Eigen::VectorXd force;
  internal_force(finite_strain_model(), full_displacement(q), force);
  f -= restrict(force);
}

void FeBody::stiffness_product(const ConstVectorRef& q, VectorRef product) const {
  product.noalias() = stiffness_ * q;
}

double FeBody::strain_energy(const ConstVectorRef& q) const {
  if (!finite_strain_) return 0.5 * q.dot(stiffness_ * q);
  return csim::strain_energy(finite_strain_model(), full_displacement(q));
}

void FeBody::add_tangent_stiffness(const ConstVectorRef& q, int offset, Triplets& stiffness) const {
  if (!finite_strain_) {
    add_stiffness(offset, stiffness);
    return;
  }
  Triplets element;
  tangent_triplets(finite_strain_model(), full_displacement(q), element);
  append_free(element, offset, stiffness);
}

void FeBody::add_internal_force_and_tangent(const ConstVectorRef& q, VectorRef f, int offset,
                                            Triplets& stiffness) const {
  if (!finite_strain_) {
    Body::add_internal_force_and_tangent(q, f, offset, stiffness);
    return;
  }
  Eigen::VectorXd force;
  assemble_finite_strain(finite_strain_model(), full_displacement(q), force, {free_of_dof_, offset}, stiffness);
  f -= restrict(force);
}

void FeBody::append_free(const Triplets& element, int offset, Triplets& stiffness) const {
  stiffness.reserve(stiffness.size() + element.size());
  for (const auto& entry : element) {
    const int i = free_of_dof_[entry.row()], j = free_of_dof_[entry.col()];
    if (i >= 0 && j >= 0) stiffness.emplace_back(offset + i, offset + j, entry.value());
  }
}

// Exact reference coordinates (contacts pass a node's own) are found at once; a point typed by a user
// (a spring's or a probe's) within 1e-9 of the mesh size by a search.
int FeBody::node_at(const Eigen::Vector3d& point) const {
  if (const auto it = node_of_coordinates_.find(point); it != node_of_coordinates_.end()) return it->second;
  for (std::size_t i = 0; i < mesh_.nodes.size(); ++i)
    if ((mesh_.nodes[i] - point).norm() <= 1e-9 * size_) return static_cast<int>(i);
  return -1;
}

Eigen::Vector3d FeBody::node_displacement(const ConstVectorRef& q, int node) const {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  for (int c = 0; c < dofs_per_node(); ++c) {
    const int i = free_index(node, c);
    if (i >= 0) u(c) = q(i);
  }
  return u;
}

Eigen::Vector3d FeBody::displacement_at(const ConstVectorRef& q, const MeshPoint& point) const {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  for (int a = 0; a < point.count; ++a) u += point.weights[a] * node_displacement(q, point.nodes[a]);
  return u;
}

// A node's own displacement where the point is one (to the bit, as springs and contacts see it);
// elsewhere the elements' interpolation; a point outside the body stays where it is (the scene loader
// refuses such probes).
Eigen::Vector3d FeBody::point_world(const ConstVectorRef& q, const Eigen::Vector3d& local) const {
  if (const int node = node_at(local); node >= 0) return local + node_displacement(q, node);
  const std::optional<MeshPoint> point = locate(local);
  return point ? Eigen::Vector3d(local + displacement_at(q, *point)) : local;
}

PointJacobian FeBody::point_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& local) const {
  const int node = node_at(local);
  if (node < 0) return {};
  return surface_point_jacobian(q, SurfacePoint::at_node(node));
}

PointJacobian FeBody::surface_point_jacobian(const ConstVectorRef&, const SurfacePoint& point) const {
  PointJacobian J;
  for (int k = 0; k < point.count; ++k) {
    if (point.weights[k] == 0.0) continue;  // a face point on a corner: the other nodes do not move it
    for (int c = 0; c < dofs_per_node(); ++c) {
      const int i = free_index(point.nodes[k], c);
      if (i >= 0) J.add(i, point.weights[k] * Eigen::Vector3d::Unit(c));
    }
  }
  return J;
}

std::optional<ContactSurface> FeBody::contact_surface(bool smoothed) const {
  ContactSurface surface;
  surface.reference_nodes = mesh_.nodes;
  DeformableSurfaceGeometry& geometry = surface.geometry;
  const std::vector<Face> faces = boundary_faces(mesh_);
  std::vector<std::array<int, 2>> edges;            // quad4 boundary: the Catmull–Rom curve's nodes
  std::vector<std::array<int, 3>> quadratic_edges;  // quad8 boundary: its curved edges
  for (const Face& f : faces) {
    if (f.nodes.size() == 2) {
      geometry.segments.push_back({f.nodes[0], f.nodes[1]});
      edges.push_back({f.nodes[0], f.nodes[1]});
    } else if (mesh_.dimension() == 2) {  // quad8 edge: corner, corner, mid-side
      geometry.segments.push_back({f.nodes[0], f.nodes[2]});
      geometry.segments.push_back({f.nodes[2], f.nodes[1]});
      quadratic_edges.push_back({f.nodes[0], f.nodes[1], f.nodes[2]});
    } else {
      geometry.triangles.push_back({f.nodes[0], f.nodes[1], f.nodes[2]});
      geometry.triangles.push_back({f.nodes[0], f.nodes[2], f.nodes[3]});
    }
  }
  geometry.contact_nodes = nodes_of(faces);
  if (smoothed) {
    geometry.curve = catmull_rom_segments(edges, mesh_.nodes);
    const std::vector<CurveSegment> quadratic = quadratic_segments(quadratic_edges);
    geometry.curve.insert(geometry.curve.end(), quadratic.begin(), quadratic.end());
  }
  return surface;
}

void FeBody::surface_node_positions(const ConstVectorRef& q, const std::vector<int>& nodes,
                                    std::vector<Eigen::Vector3d>& positions) const {
  if (positions.size() != mesh_.nodes.size()) positions.assign(mesh_.nodes.begin(), mesh_.nodes.end());
  for (int n : nodes) positions[n] = mesh_.nodes[n] + node_displacement(q, n);
}

void FeBody::add_weight(const ConstVectorRef&, const Eigen::Vector3d& g, VectorRef f) const {
  Eigen::VectorXd uniform(free_count_);
  for (int node = 0; node < static_cast<int>(mesh_.nodes.size()); ++node)
    for (int c = 0; c < dofs_per_node(); ++c)
      if (free_index(node, c) >= 0) uniform(free_index(node, c)) = g(c);
  f += mass_ * uniform;
  // The part of ∫ Nᵀ ρ g dV over the elements a free dof shares with fixed ones (the header).
  if (fixed_coupling_.nonZeros() > 0) f += fixed_coupling_ * g.head(dofs_per_node());
}

void FeBody::integrate_position(const ConstVectorRef& q, const ConstVectorRef& v_theta, double h,
                                VectorRef q_next) const {
  q_next = q + h * v_theta;
}

Eigen::VectorXd FeBody::full_displacement(const ConstVectorRef& q) const {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(mesh_.dof_count());
  for (int dof = 0; dof < mesh_.dof_count(); ++dof)
    if (free_of_dof_[dof] >= 0) u(dof) = q(free_of_dof_[dof]);
  return u;
}

Eigen::VectorXd FeBody::restrict(const Eigen::VectorXd& full) const {
  Eigen::VectorXd restricted(free_count_);
  for (int dof = 0; dof < mesh_.dof_count(); ++dof)
    if (free_of_dof_[dof] >= 0) restricted(free_of_dof_[dof]) = full(dof);
  return restricted;
}

}  // namespace csim
