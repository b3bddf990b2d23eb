// An elastic body discretized by finite elements (fem/): linear elasticity (small strain), or a
// hyperelastic law in total-Lagrangian finite strain (fem/finite_strain.h), then a nonlinear body.
//   q = displacements of the free dofs (m), v = their velocities (m/s); the fixed dofs are left out of
//   the World's coordinates altogether, so that nothing else needs to know about them.
//   M is constant, assembled once by fem/ and restricted to the free dofs; so is K for linear
//   elasticity. A finite-strain body's internal force and tangent are assembled at each q; its
//   add_stiffness (Rayleigh damping, linear steppers) gives the tangent at u = 0.
//   What the restriction drops: the coupling blocks M_fc, K_fc, C_fc times the fixed dofs' motion,
//   which is zero (a fixed dof never moves: u_c = v_c = a_c = 0), so M_ff, K_ff, C_ff are exact for the
//   inertia, the internal force and the damping. Not so for a load formed through M: the weight
//   ∫ Nᵀ ρ g dV on a free dof is the row of the whole M times the uniform field, (M G)_f = M_ff G_f +
//   M_fc G_c, and a consistent M couples a free node to the fixed nodes of the elements they share
//   (add_weight adds M_fc G_c).
// The mesh is in world coordinates (its pose is the identity). A material point is named by its
// reference coordinates: a node's, or any point of an element, whose motion the element's shape
// functions interpolate (point_world; a probe between nodes). Springs and loads attach to nodes
// (point_jacobian has no columns for other points: an element's 16 or 24 would not fit a
// PointJacobian); contacts use the boundary nodes.
#pragma once

#include "contact/contact_point.h"
#include "engine/bodies/body.h"
#include "fem/finite_strain.h"
#include "fem/material.h"
#include "fem/mesh.h"
#include "fem/point_location.h"

#include <Eigen/SparseCore>
#include <optional>
#include <unordered_map>

namespace csim {

// The finite-strain law of a nonlinear body.
struct FiniteStrainLaw {
  HyperelasticMaterial material;
  FiniteStrainFormulation formulation = FiniteStrainFormulation::standard;
};

class FeBody final : public Body {
 public:
  // fixed: (node, component) pairs held at zero displacement. thickness in m (plane meshes).
  // Rayleigh damping C = alpha M + beta K, alpha in 1/s and beta in s, both ≥ 0 (the damping ratio of
  // a mode of angular frequency ω is alpha / (2ω) + beta ω / 2).
  FeBody(Mesh mesh, const ElasticMaterial& material, double thickness, bool lumped_mass,
         const std::vector<std::pair<int, int>>& fixed, double alpha = 0.0, double beta = 0.0);
  // A finite-strain body: mass from law.material.density, the linearized law for add_stiffness.
  FeBody(Mesh mesh, const FiniteStrainLaw& law, double thickness, bool lumped_mass,
         const std::vector<std::pair<int, int>>& fixed, double alpha = 0.0, double beta = 0.0);

  int position_size() const override { return free_count_; }
  int velocity_size() const override { return free_count_; }
  double mass() const override { return total_mass_; }
  bool elastic() const override { return true; }
  void add_mass(int offset, Triplets& mass) const override;
  void add_stiffness(int offset, Triplets& stiffness) const override;
  void add_damping(int offset, Triplets& damping) const override;
  void add_internal_force(const ConstVectorRef& q, VectorRef f) const override;
  double strain_energy(const ConstVectorRef& q) const override;
  void stiffness_product(const ConstVectorRef& q, VectorRef product) const override;
  const SparseMatrix* linear_stiffness() const override { return finite_strain_ ? nullptr : &stiffness_; }
  bool nonlinear() const override { return finite_strain_.has_value(); }
  void add_tangent_stiffness(const ConstVectorRef& q, int offset, Triplets& stiffness) const override;
  void add_internal_force_and_tangent(const ConstVectorRef& q, VectorRef f, int offset,
                                      Triplets& stiffness) const override;

  Eigen::Isometry3d pose(const ConstVectorRef&) const override { return Eigen::Isometry3d::Identity(); }
  Eigen::Vector3d point_world(const ConstVectorRef& q, const Eigen::Vector3d& local) const override;
  PointJacobian point_jacobian(const ConstVectorRef& q, const Eigen::Vector3d& local) const override;
  // The Jacobian of a point of the boundary given by its nodes and weights (a contact's surface point):
  // Σ weight · (the node's unit columns); fixed components are left out (constant: q is unused).
  PointJacobian surface_point_jacobian(const ConstVectorRef& q, const SurfacePoint& point) const override;
  // Contact through the boundary: segments of the plane boundary (a quad8 edge as two, corner–mid-side
  // –corner), two triangles per face in space, the boundary nodes, and when smoothed the Catmull–Rom
  // curve through quad4 boundary nodes and the quadratic quad8 edges.
  std::optional<ContactSurface> contact_surface(bool smoothed) const override;
  void surface_node_positions(const ConstVectorRef& q, const std::vector<int>& nodes,
                              std::vector<Eigen::Vector3d>& positions) const override;
  int node_count() const override { return static_cast<int>(mesh_.nodes.size()); }
  int node_components() const override { return dofs_per_node(); }
  Eigen::Vector3d node_reference(int node) const override { return mesh_.nodes[node]; }
  int node_velocity_index(int node, int c) const override { return free_index(node, c); }
  const FeBody* finite_elements() const override { return this; }
  void add_weight(const ConstVectorRef& q, const Eigen::Vector3d& g, VectorRef f) const override;
  void integrate_position(const ConstVectorRef& q, const ConstVectorRef& v_theta, double h,
                          VectorRef q_next) const override;
  int velocity_index(const std::string&) const override { return -1; }

  const Mesh& mesh() const { return mesh_; }
  const ElasticMaterial& material() const { return material_; }
  double thickness() const { return thickness_; }
  // The finite-strain law and formulation, or nullopt for a linear body.
  const std::optional<FiniteStrainLaw>& finite_strain_law() const { return finite_strain_; }
  int dofs_per_node() const { return mesh_.dofs_per_node(); }
  // Index of a node's displacement component among the free dofs, or −1 when it is fixed.
  int free_index(int node, int component) const { return free_of_dof_[dofs_per_node() * node + component]; }
  Eigen::Vector3d node_displacement(const ConstVectorRef& q, int node) const;
  // The node at reference coordinates `point` (within 1e-9 of the mesh size), or −1.
  int node_at(const Eigen::Vector3d& point) const;
  // The element point at reference coordinates `point` (fem/point_location.h: a search of the
  // elements, to be done once), or nullopt when no element holds it.
  std::optional<MeshPoint> locate(const Eigen::Vector3d& point) const { return locate_point(mesh_, point); }
  // The displacement (m) at an element point, Σ_a N_a u_a (fixed components 0).
  Eigen::Vector3d displacement_at(const ConstVectorRef& q, const MeshPoint& point) const;
  // All dofs' displacement (fixed ones zero), node-major: for outputs and stresses.
  Eigen::VectorXd full_displacement(const ConstVectorRef& q) const;
  // A global force vector (N per dof of the whole mesh) restricted to the free dofs.
  Eigen::VectorXd restrict(const Eigen::VectorXd& full) const;

 private:
  void build(bool lumped_mass, const std::vector<std::pair<int, int>>& fixed);
  // Mesh-dof triplets of a finite-strain tangent restricted to the free dofs, shifted by offset.
  void append_free(const Triplets& element, int offset, Triplets& stiffness) const;
  FiniteStrainModel finite_strain_model() const {
    return {mesh_, finite_strain_->material, thickness_, finite_strain_->formulation};
  }

  Mesh mesh_;
  ElasticMaterial material_;  // a finite-strain body: the linearized law (initial moduli)
  std::optional<FiniteStrainLaw> finite_strain_;
  double thickness_;
  int free_count_ = 0;
  std::vector<int> free_of_dof_;   // mesh dof → free index or −1
  SparseMatrix mass_, stiffness_;  // restricted to the free dofs
  // M_fc summed over each fixed dof's component: entry (free dof i, component c) = Σ M(i, j) over the
  // fixed dofs j along c (kg), so that M_fc G_c = fixed_coupling_ g. Empty for a lumped M (diagonal)
  // or a body with nothing fixed; a few rows (the free dofs of elements with a fixed node) otherwise.
  SparseMatrix fixed_coupling_;
  double total_mass_ = 0.0;
  double alpha_ = 0.0, beta_ = 0.0;  // Rayleigh coefficients, 1/s and s
  double size_ = 1.0;              // m, the mesh's bounding-box diagonal
  struct CoordinatesHash {
    std::size_t operator()(const Eigen::Vector3d& x) const {
      const std::hash<double> h;
      return h(x.x()) ^ (h(x.y()) << 1) ^ (h(x.z()) << 2);
    }
  };
  std::unordered_map<Eigen::Vector3d, int, CoordinatesHash> node_of_coordinates_;  // exact reference coordinates
};

}  // namespace csim
