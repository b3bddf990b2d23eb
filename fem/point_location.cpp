#include "fem/point_location.h"

#include <algorithm>
#include <cmath>

namespace csim {

namespace {

constexpr int kNewtonIterations = 50;

// Whether x lies in the element's node box, widened for quad8 (point_location.h).
bool in_box(const ElementGeometry& element, const Eigen::Vector3d& x, int d) {
  const auto coordinates = element.coordinates.leftCols(d);
  const Eigen::VectorXd lower = coordinates.colwise().minCoeff(), upper = coordinates.colwise().maxCoeff();
  const double widen = (element.type == ElementType::quad8 ? 0.25 : kLocationTolerance) * (upper - lower).norm();
  for (int i = 0; i < d; ++i)
    if (x(i) < lower(i) - widen || x(i) > upper(i) + widen) return false;
  return true;
}

// Newton on x(ξ) = x from ξ = 0; nullopt when it does not converge or leaves the element far behind.
std::optional<Eigen::Vector3d> natural_coordinates(const ElementGeometry& element, const Eigen::Vector3d& x, int d) {
  const auto coordinates = element.coordinates.leftCols(d);
  const double size = (coordinates.colwise().maxCoeff() - coordinates.colwise().minCoeff()).norm();
  Eigen::Vector3d xi = Eigen::Vector3d::Zero();
  bool converged = false;
  for (int iteration = 0; iteration < kNewtonIterations; ++iteration) {
    const ShapeFunctions s = shape_functions(element.type, xi);
    const Eigen::VectorXd residual = x.head(d) - coordinates.transpose() * s.values;  // m
    const Eigen::MatrixXd jacobian = coordinates.transpose() * s.derivatives.leftCols(d);  // ∂x_i/∂ξ_j
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(jacobian);
    if (!lu.isInvertible()) return std::nullopt;
    xi.head(d) += lu.solve(residual);
    if (!xi.allFinite() || xi.cwiseAbs().maxCoeff() > 10.0) return std::nullopt;  // far outside: not this one
    if (converged) return xi;  // one step past 1e-12: quadratic convergence takes it to round-off
    converged = residual.norm() <= 1e-12 * size;
  }
  return std::nullopt;
}

}  // namespace

std::optional<MeshPoint> locate_point(const Mesh& mesh, const Eigen::Vector3d& x) {
  const int d = mesh.dimension();
  for (int e = 0; e < static_cast<int>(mesh.elements.size()); ++e) {
    const ElementGeometry element = element_geometry(mesh, e);
    if (!in_box(element, x, d)) continue;
    const std::optional<Eigen::Vector3d> xi = natural_coordinates(element, x, d);
    if (!xi) continue;
    const Eigen::Vector3d natural = *xi;
    if (natural.cwiseAbs().maxCoeff() > 1.0 + kLocationTolerance) continue;  // components beyond d are 0
    MeshPoint point;
    point.element = e;
    point.natural = natural.cwiseMax(-1.0).cwiseMin(1.0);  // a point on a face within round-off: on it
    const ShapeFunctions s = shape_functions(mesh.element_type, point.natural);
    point.count = static_cast<int>(mesh.elements[e].size());
    for (int a = 0; a < point.count; ++a) {
      point.nodes[a] = mesh.elements[e][a];
      point.weights[a] = s.values(a);
    }
    return point;
  }
  return std::nullopt;
}

Eigen::Vector3d interpolate(const Mesh& mesh, const MeshPoint& point, const Eigen::VectorXd& values) {
  const int d = mesh.dofs_per_node();
  Eigen::Vector3d result = Eigen::Vector3d::Zero();
  for (int a = 0; a < point.count; ++a) result.head(d) += point.weights[a] * values.segment(d * point.nodes[a], d);
  return result;
}

}  // namespace csim
