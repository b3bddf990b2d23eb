// Direct-stiffness assembly of assembly.h: each element matrix is computed once in fixed-size
// storage (elements.cpp) and scattered into a reserved triplet list; Eigen sums the duplicates when
// it compresses the list into the column-major sparse matrix.
#include "fem/assembly.h"

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace csim {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

// Global dof of component i of local node a of element e: d·node + i (node-major).
int global_dof(const Mesh& mesh, int element, int a, int i) {
  return mesh.dofs_per_node() * mesh.elements[element][a] + i;
}

void check_thickness(const FeModel& model) {
  if (model.mesh.dimension() == 2 &&
      (!(model.thickness > 0.0) || !std::isfinite(model.thickness))) {
    std::ostringstream message;
    message << "thickness = " << model.thickness << " m must be > 0 for a plane-strain mesh";
    throw FemError(message.str());
  }
}

void check_size(const char* what, Eigen::Index size, Eigen::Index expected) {
  if (size != expected) {
    throw FemError(std::string(what) + " has " + std::to_string(size) + " entries, expected " +
                   std::to_string(expected) + " (the model's dofs)");
  }
}

}  // namespace

void check_mesh(const Mesh& mesh) {
  for (int e = 0; e < static_cast<int>(mesh.elements.size()); ++e) {
    // A quad4 with nodes 1 2 2 3 is a triangle whose Jacobian stays positive at every Gauss point, but
    // whose collapsed edge matches no neighbour's: a hole in the mesh that no other check sees.
    std::vector<int> nodes = mesh.elements[e];
    std::sort(nodes.begin(), nodes.end());
    if (const auto twice = std::adjacent_find(nodes.begin(), nodes.end()); twice != nodes.end())
      throw FemError("element " + std::to_string(e) + " lists node " + std::to_string(*twice) +
                     " twice: a degenerate " + to_string(mesh.element_type) + " leaves a hole in the mesh");
    jacobian_determinants(element_geometry(mesh, e));
  }
}

Eigen::SparseMatrix<double> assemble_stiffness(const FeModel& model) {
  const Mesh& mesh = model.mesh;
  check_material(model.material);
  check_thickness(model);
  const int element_count = static_cast<int>(mesh.elements.size());
  const int d = mesh.dofs_per_node();
  Triplets triplets;
  if (element_count > 0) {
    const int element_dofs = d * static_cast<int>(mesh.elements.front().size());
    triplets.reserve(static_cast<std::size_t>(element_count) * element_dofs * element_dofs);
  }
  for (int e = 0; e < element_count; ++e) {
    const ElementMatrix K =
        element_stiffness(element_geometry(mesh, e), model.material, model.thickness);
    const int n = static_cast<int>(K.rows()) / d;
    for (int b = 0; b < n; ++b)
      for (int j = 0; j < d; ++j) {
        const int column = global_dof(mesh, e, b, j);
        for (int a = 0; a < n; ++a)
          for (int i = 0; i < d; ++i)
            triplets.emplace_back(global_dof(mesh, e, a, i), column, K(d * a + i, d * b + j));
      }
  }
  Eigen::SparseMatrix<double> K(mesh.dof_count(), mesh.dof_count());
  K.setFromTriplets(triplets.begin(), triplets.end());
  return K;
}

Eigen::SparseMatrix<double> assemble_mass(const FeModel& model, bool lumped) {
  const Mesh& mesh = model.mesh;
  check_material(model.material);
  check_thickness(model);
  const int element_count = static_cast<int>(mesh.elements.size());
  const int d = mesh.dofs_per_node();
  const double density = model.material.density;
  Triplets triplets;
  if (element_count > 0) {
    const int n = static_cast<int>(mesh.elements.front().size());
    triplets.reserve(static_cast<std::size_t>(element_count) * d * (lumped ? n : n * n));
  }
  for (int e = 0; e < element_count; ++e) {
    const ElementGeometry geometry = element_geometry(mesh, e);
    const int n = static_cast<int>(geometry.coordinates.rows());
    if (lumped) {
      const ElementVector m = element_lumped_mass(geometry, density, model.thickness);
      for (int a = 0; a < n; ++a)
        for (int i = 0; i < d; ++i) {
          const int dof = global_dof(mesh, e, a, i);
          triplets.emplace_back(dof, dof, m(d * a + i));
        }
    } else {
      // Only the direction-diagonal blocks: the consistent mass does not couple x, y, z.
      const ElementMatrix M = element_consistent_mass(geometry, density, model.thickness);
      for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a)
          for (int i = 0; i < d; ++i)
            triplets.emplace_back(global_dof(mesh, e, a, i), global_dof(mesh, e, b, i),
                                  M(d * a + i, d * b + i));
    }
  }
  Eigen::SparseMatrix<double> M(mesh.dof_count(), mesh.dof_count());
  M.setFromTriplets(triplets.begin(), triplets.end());
  return M;
}

Eigen::VectorXd pressure_load(const FeModel& model, const std::vector<Face>& faces,
                              double pressure) {
  const Mesh& mesh = model.mesh;
  check_thickness(model);
  const int d = mesh.dofs_per_node();
  const int n = nodes_per_face(mesh.element_type);
  const int node_count = static_cast<int>(mesh.nodes.size());
  Eigen::VectorXd load = Eigen::VectorXd::Zero(mesh.dof_count());
  for (int k = 0; k < static_cast<int>(faces.size()); ++k) {
    const Face& face = faces[k];
    const std::string name =
        "face " + std::to_string(k) + " (element " + std::to_string(face.element) + ")";
    if (static_cast<int>(face.nodes.size()) != n) {
      throw FemError(name + " has " + std::to_string(face.nodes.size()) + " nodes, a face of a " +
                     to_string(mesh.element_type) + " has " + std::to_string(n));
    }
    NodeCoordinates x(n, 3);
    for (int a = 0; a < n; ++a) {
      if (face.nodes[a] < 0 || face.nodes[a] >= node_count) {
        throw FemError(name + ": node index " + std::to_string(face.nodes[a]) +
                       " out of range (the mesh has " + std::to_string(node_count) + " nodes)");
      }
      x.row(a) = mesh.nodes[face.nodes[a]].transpose();
    }
    const ElementVector f =
        face_pressure_forces(mesh.element_type, x, pressure, model.thickness, face.element);
    for (int a = 0; a < n; ++a) load.segment(d * face.nodes[a], d) += f.segment(d * a, d);
  }
  return load;
}

std::vector<Stress> element_stresses(const FeModel& model, const Eigen::VectorXd& displacement) {
  const Mesh& mesh = model.mesh;
  check_material(model.material);
  check_size("the displacement", displacement.size(), mesh.dof_count());
  std::vector<Stress> stresses;
  CentroidStressMap(mesh, model.material).stresses(displacement, stresses);
  return stresses;
}

double strain_energy(const Eigen::SparseMatrix<double>& K, const Eigen::VectorXd& u) {
  if (K.rows() != K.cols()) throw FemError("strain_energy: the stiffness matrix is not square");
  check_size("the displacement", u.size(), K.rows());
  return 0.5 * u.dot(K * u);
}

}  // namespace csim
