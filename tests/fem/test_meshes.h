// Small structured meshes built in code for the element and assembly tests, and a direct solve of
// K u = f with prescribed dofs. Independent of fem/mesh_generators so that these tests check the
// elements against hand-built geometry.
#pragma once

#include "fem/mesh.h"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <vector>

namespace csim::test {

// [0, lx] × [0, ly] (m) in nx × ny quad4 or quad8 elements, node order of mesh.h. Node sets
// left, right, bottom, top and boundary; face sets left, right, bottom, top with the nodes in the
// order that makes (t_y, −t_x) the outward normal (mesh.h).
inline Mesh rectangle(ElementType type, int nx, int ny, double lx, double ly) {
  const int s = type == ElementType::quad8 ? 2 : 1;  // lattice steps per element side
  const int columns = s * nx + 1, rows = s * ny + 1;
  Mesh mesh;
  mesh.element_type = type;
  std::vector<int> id(columns * rows, -1);
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < columns; ++i) {
      if (s == 2 && i % 2 == 1 && j % 2 == 1) continue;  // no centre node in a serendipity element
      const int node = static_cast<int>(mesh.nodes.size());
      id[j * columns + i] = node;
      mesh.nodes.emplace_back(lx * i / (s * nx), ly * j / (s * ny), 0.0);
      const bool left = i == 0, right = i == columns - 1, bottom = j == 0, top = j == rows - 1;
      if (left) mesh.node_sets["left"].push_back(node);
      if (right) mesh.node_sets["right"].push_back(node);
      if (bottom) mesh.node_sets["bottom"].push_back(node);
      if (top) mesh.node_sets["top"].push_back(node);
      if (left || right || bottom || top) mesh.node_sets["boundary"].push_back(node);
    }
  auto at = [&](int i, int j) { return id[j * columns + i]; };
  for (int ey = 0; ey < ny; ++ey)
    for (int ex = 0; ex < nx; ++ex) {
      const int i = s * ex, j = s * ey, e = static_cast<int>(mesh.elements.size());
      std::vector<int> nodes{at(i, j), at(i + s, j), at(i + s, j + s), at(i, j + s)};
      if (s == 2)
        nodes.insert(nodes.end(), {at(i + 1, j), at(i + 2, j + 1), at(i + 1, j + 2), at(i, j + 1)});
      // Edge k runs from corner k to corner k+1 (mid-side node 4 + k): counter-clockwise, outward.
      auto edge = [&](int k) {
        Face face{e, k, {nodes[k], nodes[(k + 1) % 4]}};
        if (s == 2) face.nodes.push_back(nodes[4 + k]);
        return face;
      };
      if (ey == 0) mesh.face_sets["bottom"].push_back(edge(0));
      if (ex == nx - 1) mesh.face_sets["right"].push_back(edge(1));
      if (ey == ny - 1) mesh.face_sets["top"].push_back(edge(2));
      if (ex == 0) mesh.face_sets["left"].push_back(edge(3));
      mesh.elements.push_back(std::move(nodes));
    }
  return mesh;
}

// [0, lx] × [0, ly] × [0, lz] (m) in nx × ny × nz hexa8. Node sets left/right (x), bottom/top (y),
// back/front (z) and boundary; face sets with the same names, nodes counter-clockwise from outside.
inline Mesh box(int nx, int ny, int nz, double lx, double ly, double lz) {
  Mesh mesh;
  mesh.element_type = ElementType::hexa8;
  auto at = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const int node = at(i, j, k);
        mesh.nodes.emplace_back(lx * i / nx, ly * j / ny, lz * k / nz);
        const std::pair<bool, const char*> sides[] = {{i == 0, "left"},   {i == nx, "right"},
                                                      {j == 0, "bottom"}, {j == ny, "top"},
                                                      {k == 0, "back"},   {k == nz, "front"}};
        bool boundary = false;
        for (const auto& [on, name] : sides)
          if (on) mesh.node_sets[name].push_back(node), boundary = true;
        if (boundary) mesh.node_sets["boundary"].push_back(node);
      }
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int e = static_cast<int>(mesh.elements.size());
        const std::vector<int> n{
            at(i, j, k),     at(i + 1, j, k),     at(i + 1, j + 1, k),     at(i, j + 1, k),
            at(i, j, k + 1), at(i + 1, j, k + 1), at(i + 1, j + 1, k + 1), at(i, j + 1, k + 1)};
        if (i == 0) mesh.face_sets["left"].push_back({e, 0, {n[0], n[4], n[7], n[3]}});
        if (i == nx - 1) mesh.face_sets["right"].push_back({e, 1, {n[1], n[2], n[6], n[5]}});
        if (j == 0) mesh.face_sets["bottom"].push_back({e, 2, {n[0], n[1], n[5], n[4]}});
        if (j == ny - 1) mesh.face_sets["top"].push_back({e, 3, {n[3], n[7], n[6], n[2]}});
        if (k == 0) mesh.face_sets["back"].push_back({e, 4, {n[0], n[3], n[2], n[1]}});
        if (k == nz - 1) mesh.face_sets["front"].push_back({e, 5, {n[4], n[5], n[6], n[7]}});
        mesh.elements.push_back(n);
      }
  return mesh;
}

// Moves every node (or only those not in the "boundary" set) by a deterministic pseudo-random
// offset of at most `amplitude` (m) per component; z is moved only in 3D meshes.
inline void distort(Mesh& mesh, double amplitude, bool interior_only = false) {
  const std::vector<int>& boundary = mesh.node_sets["boundary"];
  const bool solid = mesh.element_type == ElementType::hexa8;
  for (int i = 0; i < static_cast<int>(mesh.nodes.size()); ++i) {
    if (interior_only && std::binary_search(boundary.begin(), boundary.end(), i)) continue;
    mesh.nodes[i] += amplitude * Eigen::Vector3d(std::sin(1.7 * i + 0.3), std::cos(2.3 * i + 1.1),
                                                 solid ? std::sin(3.1 * i + 0.7) : 0.0);
  }
}

// Solves K u = f for the free dofs with u = value on the prescribed ones (sparse LDLᵀ; K symmetric
// positive definite on the free dofs).
inline Eigen::VectorXd solve(const Eigen::SparseMatrix<double>& K, const Eigen::VectorXd& f,
                             const std::map<int, double>& prescribed) {
  const int n = static_cast<int>(K.rows());
  std::vector<int> free_index(n, -1);
  int free_count = 0;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
  for (int dof = 0; dof < n; ++dof) {
    const auto fixed = prescribed.find(dof);
    if (fixed == prescribed.end())
      free_index[dof] = free_count++;
    else
      u(dof) = fixed->second;
  }
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::VectorXd rhs(free_count);
  for (int dof = 0; dof < n; ++dof)
    if (free_index[dof] >= 0) rhs(free_index[dof]) = f(dof);
  for (int column = 0; column < K.outerSize(); ++column)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, column); it; ++it) {
      const int row = static_cast<int>(it.row());
      if (free_index[row] < 0) continue;
      if (free_index[column] >= 0)
        triplets.emplace_back(free_index[row], free_index[column], it.value());
      else
        rhs(free_index[row]) -= it.value() * u(column);
    }
  Eigen::SparseMatrix<double> K_free(free_count, free_count);
  K_free.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factorization(K_free);
  if (factorization.info() != Eigen::Success) throw std::runtime_error("singular stiffness");
  const Eigen::VectorXd u_free = factorization.solve(rhs);
  for (int dof = 0; dof < n; ++dof)
    if (free_index[dof] >= 0) u(dof) = u_free(free_index[dof]);
  return u;
}

}  // namespace csim::test
