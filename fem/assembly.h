// Global matrices and vectors of a linear-elastic finite-element model (small strain).
//
// Dofs are node-major: node i has the dofs [d·i, d·i + d), d = 2 (plane strain) or 3, displacement
// components x, y (, z) in m. The global matrices are the standard direct-stiffness sums
// K = Σ_e A_eᵀ K_e A_e (Hughes, The Finite Element Method, §1.14 and §2.8), built once from
// triplets (duplicates summed) as column-major Eigen::SparseMatrix, symmetric, with the structural
// pattern of the mesh (entries that cancel numerically are kept).
#pragma once

#include "fem/elements.h"
#include "fem/material.h"
#include "fem/mesh.h"

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <vector>

namespace csim {

// What the assembly needs: a mesh (not owned; it must outlive the model), one material for all
// elements, and the out-of-plane thickness of plane-strain meshes (m; ignored for hexa8).
struct FeModel {
  const Mesh& mesh;
  ElasticMaterial material;
  double thickness = 1.0;  // m
};

// Throws FemError naming the first bad element (its index): wrong node count, node index out of range, a
// node listed twice, or a Jacobian det J ≤ 0 at one of its Gauss points (an inverted or degenerate element).
void check_mesh(const Mesh& mesh);

// Stiffness K (N/m), dof_count × dof_count. Checks the material and every element.
Eigen::SparseMatrix<double> assemble_stiffness(const FeModel& model);

// Mass M (kg): consistent (∫ ρ Nᵀ N dV) or lumped (diagonal; row-sum, HRZ for quad8, see
// elements.h). Both give 1ᵀ M_x 1 = ρ V per direction (V = area × thickness in 2D).
Eigen::SparseMatrix<double> assemble_mass(const FeModel& model, bool lumped);

// Equivalent nodal forces (N per dof, dof_count entries) of a uniform pressure p (Pa) on the faces:
// positive p pushes INTO the body (traction −p n, n the outward normal of mesh.h's Face
// convention); a negative p pulls, e.g. a tensile traction. Throws FemError naming the face (its
// position in the list and its element) when its node count or a node index is wrong.
Eigen::VectorXd pressure_load(const FeModel& model, const std::vector<Face>& faces,
                              double pressure);

// Stress at each element's centroid (Pa), (σxx, σyy, σzz, σxy, σyz, σxz), from the global
// displacement (m, dof_count entries); plane strain: σzz = ν(σxx + σyy). A CentroidStressMap
// (elements.h) formed for this call; keep one for frame after frame.
std::vector<Stress> element_stresses(const FeModel& model, const Eigen::VectorXd& displacement);

// ½ uᵀ K u, J (K in N/m, u in m).
double strain_energy(const Eigen::SparseMatrix<double>& K, const Eigen::VectorXd& u);

}  // namespace csim
