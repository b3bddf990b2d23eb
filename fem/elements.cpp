// Element kernels of elements.h. Each element type is a small traits struct (node count, dimension,
// Gauss points per direction, shape functions); the kernels are templates on it so that every
// matrix has a fixed size, and the shape functions at the Gauss points are computed once per type.
#include "fem/elements.h"

#include "fem/element_dispatch.h"

#include <array>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

namespace csim {
namespace {

// Corners of the reference square in the order of mesh.h (counter-clockwise from (−1, −1)).
constexpr std::array<std::array<double, 2>, 4> kSquareCorners{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};

template <int Nodes, int Dimension>
struct Shape {
  Eigen::Matrix<double, Nodes, 1> N;           // N_a
  Eigen::Matrix<double, Nodes, Dimension> dN;  // ∂N_a/∂ξ_j
};

// Bilinear Lagrange element (Hughes §3.2).
struct Quad4 {
  static constexpr ElementType type = ElementType::quad4;
  static constexpr int nodes = 4, dimension = 2, gauss_per_direction = 2;
  static Shape<4, 2> shape(const Eigen::Vector3d& xi) {
    Shape<4, 2> s;
    for (int a = 0; a < 4; ++a) {
      const double xa = kSquareCorners[a][0], ya = kSquareCorners[a][1];
      s.N(a) = 0.25 * (1 + xi.x() * xa) * (1 + xi.y() * ya);
      s.dN(a, 0) = 0.25 * xa * (1 + xi.y() * ya);
      s.dN(a, 1) = 0.25 * ya * (1 + xi.x() * xa);
    }
    return s;
  }
};

// Eight-node serendipity element (Zienkiewicz & Taylor vol. 1, §6.3): corners
// N = ¼(1 + ξξa)(1 + ηηa)(ξξa + ηηa − 1), mid-sides N = ½(1 − ξ²)(1 + ηηa) or ½(1 + ξξa)(1 − η²).
struct Quad8 {
  static constexpr ElementType type = ElementType::quad8;
  static constexpr int nodes = 8, dimension = 2, gauss_per_direction = 3;
  static Shape<8, 2> shape(const Eigen::Vector3d& xi) {
    const double x = xi.x(), y = xi.y();
    Shape<8, 2> s;
    for (int a = 0; a < 4; ++a) {
      const double xa = kSquareCorners[a][0], ya = kSquareCorners[a][1];
      s.N(a) = 0.25 * (1 + x * xa) * (1 + y * ya) * (x * xa + y * ya - 1);
      s.dN(a, 0) = 0.25 * xa * (1 + y * ya) * (2 * x * xa + y * ya);
      s.dN(a, 1) = 0.25 * ya * (1 + x * xa) * (x * xa + 2 * y * ya);
    }
    // Mid-sides of edges 0-1 (η = −1) and 2-3 (η = +1).
    for (const auto& [a, ya] : {std::pair{4, -1.0}, std::pair{6, 1.0}}) {
      s.N(a) = 0.5 * (1 - x * x) * (1 + y * ya);
      s.dN(a, 0) = -x * (1 + y * ya);
      s.dN(a, 1) = 0.5 * (1 - x * x) * ya;
    }
    // Mid-sides of edges 1-2 (ξ = +1) and 3-0 (ξ = −1).
    for (const auto& [a, xa] : {std::pair{5, 1.0}, std::pair{7, -1.0}}) {
      s.N(a) = 0.5 * (1 + x * xa) * (1 - y * y);
      s.dN(a, 0) = 0.5 * xa * (1 - y * y);
      s.dN(a, 1) = -y * (1 + x * xa);
    }
    return s;
  }
};

// Trilinear Lagrange brick (Hughes §3.5): N = ⅛(1 + ξξa)(1 + ηηa)(1 + ζζa).
struct Hexa8 {
  static constexpr ElementType type = ElementType::hexa8;
  static constexpr int nodes = 8, dimension = 3, gauss_per_direction = 2;
  static Shape<8, 3> shape(const Eigen::Vector3d& xi) {
    Shape<8, 3> s;
    for (int a = 0; a < 8; ++a) {
      const double xa = kSquareCorners[a % 4][0], ya = kSquareCorners[a % 4][1];
      const double za = a < 4 ? -1.0 : 1.0;
      const double fx = 1 + xi.x() * xa, fy = 1 + xi.y() * ya, fz = 1 + xi.z() * za;
      s.N(a) = 0.125 * fx * fy * fz;
      s.dN(a, 0) = 0.125 * xa * fy * fz;
      s.dN(a, 1) = 0.125 * ya * fx * fz;
      s.dN(a, 2) = 0.125 * za * fx * fy;
    }
    return s;
  }
};

template <class Function>
decltype(auto) dispatch(ElementType type, Function&& f) {
  return dispatch_element<Quad4, Quad8, Hexa8>(type, std::forward<Function>(f));
}

// The shape functions at the points of the full rule, computed once per element type.
template <class E>
struct GaussData {
  static constexpr int count =
      E::dimension == 2 ? E::gauss_per_direction * E::gauss_per_direction
                        : E::gauss_per_direction * E::gauss_per_direction * E::gauss_per_direction;
  std::array<Eigen::Vector3d, count> natural;
  std::array<double, count> weight;
  std::array<Shape<E::nodes, E::dimension>, count> shape;
};

template <class E>
const GaussData<E>& gauss_data() {
  static const GaussData<E> data = [] {
    GaussData<E> d;
    const std::vector<GaussPoint> rule = gauss_rule(E::type);
    for (int g = 0; g < GaussData<E>::count; ++g) {
      d.natural[g] = rule[g].natural;
      d.weight[g] = rule[g].weight;
      d.shape[g] = E::shape(rule[g].natural);
    }
    return d;
  }();
  return data;
}

[[noreturn]] void throw_non_positive_jacobian(int element, double determinant,
                                              const Eigen::Vector3d& natural) {
  std::ostringstream message;
  message << "element " << element
          << " has a non-positive Jacobian (inverted or degenerate): det J = " << determinant
          << " at ξ = (" << natural.x() << ", " << natural.y() << ", " << natural.z() << ")";
  throw FemError(message.str());
}

template <int Dimension>
double checked_determinant(const Eigen::Matrix<double, Dimension, Dimension>& J, int element,
                           const Eigen::Vector3d& natural) {
  const double determinant = J.determinant();
  if (!(determinant > 0.0) || !std::isfinite(determinant))
    throw_non_positive_jacobian(element, determinant, natural);
  return determinant;
}

template <class E>
using Coordinates = Eigen::Matrix<double, E::nodes, E::dimension>;  // m, one row per node

template <class E>
Coordinates<E> fixed_coordinates(const ElementGeometry& element) {
  if (element.coordinates.rows() != E::nodes) {
    throw FemError("element " + std::to_string(element.index) + " has " +
                   std::to_string(element.coordinates.rows()) + " nodes, a " + to_string(E::type) +
                   " has " + std::to_string(E::nodes));
  }
  return element.coordinates.template leftCols<E::dimension>();
}

// ∂N/∂x at one point from ∂N/∂ξ: J = xᵀ ∂N/∂ξ, ∂N/∂x = ∂N/∂ξ J⁻¹. Returns det J after checking it.
template <class E>
double physical_gradients(const Coordinates<E>& x, const Shape<E::nodes, E::dimension>& shape,
                          int element, const Eigen::Vector3d& natural,
                          Eigen::Matrix<double, E::nodes, E::dimension>& dN_dx) {
  const Eigen::Matrix<double, E::dimension, E::dimension> J = x.transpose() * shape.dN;
  const double determinant = checked_determinant(J, element, natural);
  dN_dx.noalias() = shape.dN * J.inverse();
  return determinant;
}

// Strain–displacement matrices B (ε = B u_e), Hughes §2.8 and §3.10; engineering shears.
template <int Nodes>
Eigen::Matrix<double, 3, 2 * Nodes> strain_displacement(const Eigen::Matrix<double, Nodes, 2>& g) {
  Eigen::Matrix<double, 3, 2 * Nodes> B = Eigen::Matrix<double, 3, 2 * Nodes>::Zero();
  for (int a = 0; a < Nodes; ++a) {
    B(0, 2 * a) = g(a, 0);
    B(1, 2 * a + 1) = g(a, 1);
    B(2, 2 * a) = g(a, 1);
    B(2, 2 * a + 1) = g(a, 0);
  }
  return B;
}
template <int Nodes>
Eigen::Matrix<double, 6, 3 * Nodes> strain_displacement(const Eigen::Matrix<double, Nodes, 3>& g) {
  Eigen::Matrix<double, 6, 3 * Nodes> B = Eigen::Matrix<double, 6, 3 * Nodes>::Zero();
  for (int a = 0; a < Nodes; ++a) {
    const int c = 3 * a;
    B(0, c) = g(a, 0);
    B(1, c + 1) = g(a, 1);
    B(2, c + 2) = g(a, 2);
    B(3, c) = g(a, 1), B(3, c + 1) = g(a, 0);      // γxy
    B(4, c + 1) = g(a, 2), B(4, c + 2) = g(a, 1);  // γyz
    B(5, c) = g(a, 2), B(5, c + 2) = g(a, 0);      // γxz
  }
  return B;
}

// Elasticity matrix D (σ = D ε), Pa: plane strain (3×3) or 3D (6×6), Hughes §2.7.
template <int Dimension>
auto elasticity(const ElasticMaterial& material) {
  const double lambda = lame_lambda(material), mu = shear_modulus(material);
  constexpr int size = Dimension == 2 ? 3 : 6;
  Eigen::Matrix<double, size, size> D = Eigen::Matrix<double, size, size>::Zero();
  for (int i = 0; i < Dimension; ++i) {
    for (int j = 0; j < Dimension; ++j) D(i, j) = lambda;
    D(i, i) = lambda + 2 * mu;
  }
  for (int i = Dimension; i < size; ++i) D(i, i) = mu;
  return D;
}

// t for plane elements (checked), 1 for solids: dV = scale · det J dξ.
template <class E>
double volume_scale(double thickness, int element) {
  if constexpr (E::dimension == 3) {
    return 1.0;
  } else {
    if (!(thickness > 0.0) || !std::isfinite(thickness)) {
      std::ostringstream message;
      message << "element " << element << ": thickness = " << thickness << " m must be > 0";
      throw FemError(message.str());
    }
    return thickness;
  }
}

template <class E>
ElementMatrix stiffness(const ElementGeometry& element, const ElasticMaterial& material,
                        double thickness) {
  constexpr int dofs = E::nodes * E::dimension;
  const Coordinates<E> x = fixed_coordinates<E>(element);
  const double scale = volume_scale<E>(thickness, element.index);
  const auto D = elasticity<E::dimension>(material);
  const GaussData<E>& rule = gauss_data<E>();
  Eigen::Matrix<double, dofs, dofs> K = Eigen::Matrix<double, dofs, dofs>::Zero();
  Eigen::Matrix<double, E::nodes, E::dimension> dN_dx;
  for (int g = 0; g < rule.count; ++g) {
    const double det =
        physical_gradients<E>(x, rule.shape[g], element.index, rule.natural[g], dN_dx);
    const auto B = strain_displacement<E::nodes>(dN_dx);
    K.noalias() += (rule.weight[g] * det * scale) * (B.transpose() * (D * B));
  }
  // Exactly symmetric (round-off in Bᵀ(DB) is not), as Cholesky-type solvers of K assume.
  return 0.5 * (K + K.transpose());
}

// The scalar mass m_ab = ∫ ρ N_a N_b dV (kg), common to every direction.
template <class E>
Eigen::Matrix<double, E::nodes, E::nodes> scalar_mass(const ElementGeometry& element,
                                                      double density, double thickness) {
  const Coordinates<E> x = fixed_coordinates<E>(element);
  const double scale = volume_scale<E>(thickness, element.index);
  const GaussData<E>& rule = gauss_data<E>();
  Eigen::Matrix<double, E::nodes, E::nodes> m = Eigen::Matrix<double, E::nodes, E::nodes>::Zero();
  for (int g = 0; g < rule.count; ++g) {
    const auto& s = rule.shape[g];
    const double det =
        checked_determinant(Eigen::Matrix<double, E::dimension, E::dimension>(x.transpose() * s.dN),
                            element.index, rule.natural[g]);
    m.noalias() += (density * rule.weight[g] * det * scale) * (s.N * s.N.transpose());
  }
  return m;
}

void check_density(double density, int element) {
  if (!(density >= 0.0) || !std::isfinite(density)) {
    std::ostringstream message;
    message << "element " << element << ": density = " << density << " kg/m³ must be ≥ 0";
    throw FemError(message.str());
  }
}

}  // namespace

ShapeFunctions shape_functions(ElementType type, const Eigen::Vector3d& natural) {
  return dispatch(type, [&](auto e) {
    using E = decltype(e);
    const auto s = E::shape(natural);
    return ShapeFunctions{s.N, s.dN};
  });
}

std::vector<Eigen::Vector3d> reference_nodes(ElementType type) {
  std::vector<Eigen::Vector3d> nodes;
  for (const auto& [x, y] : kSquareCorners)
    nodes.emplace_back(x, y, type == ElementType::hexa8 ? -1 : 0);
  if (type == ElementType::quad8) {
    for (const Eigen::Vector3d& middle : {Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(1, 0, 0),
                                          Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(-1, 0, 0)})
      nodes.push_back(middle);
  }
  if (type == ElementType::hexa8) {
    for (const auto& [x, y] : kSquareCorners) nodes.emplace_back(x, y, 1);
  }
  return nodes;
}

std::vector<GaussPoint> gauss_legendre(int points) {
  auto point = [](double x, double w) { return GaussPoint{Eigen::Vector3d(x, 0, 0), w}; };
  switch (points) {
    case 1: return {point(0.0, 2.0)};
    case 2: {
      const double x = 1.0 / std::sqrt(3.0);
      return {point(-x, 1.0), point(x, 1.0)};
    }
    case 3: {
      const double x = std::sqrt(0.6);
      return {point(-x, 5.0 / 9.0), point(0.0, 8.0 / 9.0), point(x, 5.0 / 9.0)};
    }
    case 4: {
      const double inner = std::sqrt(3.0 / 7.0 - 2.0 / 7.0 * std::sqrt(6.0 / 5.0));
      const double outer = std::sqrt(3.0 / 7.0 + 2.0 / 7.0 * std::sqrt(6.0 / 5.0));
      const double w_inner = (18.0 + std::sqrt(30.0)) / 36.0;
      const double w_outer = (18.0 - std::sqrt(30.0)) / 36.0;
      return {point(-outer, w_outer), point(-inner, w_inner), point(inner, w_inner),
              point(outer, w_outer)};
    }
    default:
      throw FemError("Gauss–Legendre rule with " + std::to_string(points) +
                     " points: only 1 to 4 are available");
  }
}

std::vector<GaussPoint> gauss_rule(ElementType type) {
  const std::vector<GaussPoint> line = gauss_legendre(type == ElementType::quad8 ? 3 : 2);
  const bool solid = type == ElementType::hexa8;
  std::vector<GaussPoint> rule;
  for (const GaussPoint& c :
       solid ? line : std::vector<GaussPoint>{GaussPoint{Eigen::Vector3d::Zero(), 1.0}})
    for (const GaussPoint& b : line)
      for (const GaussPoint& a : line)
        rule.push_back({Eigen::Vector3d(a.natural.x(), b.natural.x(), solid ? c.natural.x() : 0.0),
                        a.weight * b.weight * c.weight});
  return rule;
}

ElementGeometry element_geometry(const Mesh& mesh, int element) {
  const int element_count = static_cast<int>(mesh.elements.size());
  if (element < 0 || element >= element_count) {
    throw FemError("element " + std::to_string(element) + " does not exist (the mesh has " +
                   std::to_string(element_count) + " elements)");
  }
  const std::vector<int>& nodes = mesh.elements[element];
  const int expected = dispatch(mesh.element_type, [](auto e) { return decltype(e)::nodes; });
  if (static_cast<int>(nodes.size()) != expected) {
    throw FemError("element " + std::to_string(element) + " has " + std::to_string(nodes.size()) +
                   " nodes, a " + to_string(mesh.element_type) + " has " +
                   std::to_string(expected));
  }
  ElementGeometry geometry{mesh.element_type, NodeCoordinates(expected, 3), element};
  const int node_count = static_cast<int>(mesh.nodes.size());
  for (int a = 0; a < expected; ++a) {
    if (nodes[a] < 0 || nodes[a] >= node_count) {
      throw FemError("element " + std::to_string(element) + ": node index " +
                     std::to_string(nodes[a]) + " out of range (the mesh has " +
                     std::to_string(node_count) + " nodes)");
    }
    geometry.coordinates.row(a) = mesh.nodes[nodes[a]].transpose();
  }
  return geometry;
}

std::vector<double> jacobian_determinants(const ElementGeometry& element) {
  return dispatch(element.type, [&](auto e) {
    using E = decltype(e);
    const Coordinates<E> x = fixed_coordinates<E>(element);
    const GaussData<E>& rule = gauss_data<E>();
    std::vector<double> determinants;
    Eigen::Matrix<double, E::nodes, E::dimension> dN_dx;
    for (int g = 0; g < rule.count; ++g)
      determinants.push_back(
          physical_gradients<E>(x, rule.shape[g], element.index, rule.natural[g], dN_dx));
    return determinants;
  });
}

ElementMatrix element_stiffness(const ElementGeometry& element, const ElasticMaterial& material,
                                double thickness) {
  check_material(material);
  return dispatch(element.type,
                  [&](auto e) { return stiffness<decltype(e)>(element, material, thickness); });
}

ElementMatrix element_consistent_mass(const ElementGeometry& element, double density,
                                      double thickness) {
  check_density(density, element.index);
  return dispatch(element.type, [&](auto e) {
    using E = decltype(e);
    const auto m = scalar_mass<E>(element, density, thickness);
    ElementMatrix M = ElementMatrix::Zero(E::nodes * E::dimension, E::nodes * E::dimension);
    for (int a = 0; a < E::nodes; ++a)
      for (int b = 0; b < E::nodes; ++b)
        for (int i = 0; i < E::dimension; ++i)
          M(E::dimension * a + i, E::dimension * b + i) = m(a, b);
    return M;
  });
}

ElementVector element_lumped_mass(const ElementGeometry& element, double density,
                                  double thickness) {
  check_density(density, element.index);
  return dispatch(element.type, [&](auto e) {
    using E = decltype(e);
    const auto m = scalar_mass<E>(element, density, thickness);
    Eigen::Matrix<double, E::nodes, 1> nodal;
    if constexpr (E::type == ElementType::quad8) {
      // HRZ, see elements.h. The diagonal sum is > 0 (det J > 0 was checked) unless ρ = 0.
      const double diagonal_sum = m.diagonal().sum();
      nodal = diagonal_sum > 0.0 ? (m.diagonal() * (m.sum() / diagonal_sum)).eval()
                                 : Eigen::Matrix<double, E::nodes, 1>::Zero().eval();
    } else {
      nodal = m.rowwise().sum();
    }
    ElementVector lumped(E::nodes * E::dimension);
    for (int a = 0; a < E::nodes; ++a)
      lumped.segment<E::dimension>(E::dimension * a).setConstant(nodal(a));
    return lumped;
  });
}

namespace {

// ∂N/∂x at the centroid ξ = 0.
template <class E>
Eigen::Matrix<double, E::nodes, E::dimension> centroid_gradients(const ElementGeometry& element) {
  const Coordinates<E> x = fixed_coordinates<E>(element);
  const Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, E::nodes, E::dimension> dN_dx;
  physical_gradients<E>(x, E::shape(centroid), element.index, centroid, dN_dx);
  return dN_dx;
}

// σ = D (B u), in the order (xx, yy, zz, xy, yz, xz); plane strain: σzz = ν(σxx + σyy).
template <class E, class StrainDisplacement>
Stress centroid_stress(const StrainDisplacement& B, const Eigen::Matrix<double, E::nodes * E::dimension, 1>& u,
                       const ElasticMaterial& material) {
  const auto sigma = (elasticity<E::dimension>(material) * (B * u)).eval();
  Stress stress;
  if constexpr (E::dimension == 2) {
    stress << sigma(0), sigma(1), material.poisson * (sigma(0) + sigma(1)), sigma(2), 0.0, 0.0;
  } else {
    stress = sigma;
  }
  return stress;
}

}  // namespace

Stress element_centroid_stress(const ElementGeometry& element, const ElasticMaterial& material,
                               const ElementVector& displacement) {
  check_material(material);
  return dispatch(element.type, [&](auto e) -> Stress {
    using E = decltype(e);
    constexpr int dofs = E::nodes * E::dimension;
    if (displacement.size() != dofs) {
      throw FemError("element " + std::to_string(element.index) + ": " +
                     std::to_string(displacement.size()) + " displacement entries, expected " +
                     std::to_string(dofs));
    }
    const Eigen::Matrix<double, dofs, 1> u = displacement;
    return centroid_stress<E>(strain_displacement<E::nodes>(centroid_gradients<E>(element)), u, material);
  });
}

CentroidStressMap::CentroidStressMap(const Mesh& mesh, const ElasticMaterial& material)
    : mesh_(mesh), material_(material) {
  check_material(material);
  for (int e = 0; e < static_cast<int>(mesh.elements.size()); ++e) {
    const ElementGeometry element = element_geometry(mesh, e);
    dispatch(mesh.element_type, [&](auto kind) {
      const auto dN_dx = centroid_gradients<decltype(kind)>(element);
      gradients_.insert(gradients_.end(), dN_dx.data(), dN_dx.data() + dN_dx.size());
    });
  }
}

void CentroidStressMap::stresses(const Eigen::VectorXd& displacement, std::vector<Stress>& out) const {
  if (displacement.size() != mesh_.dof_count()) {
    throw FemError("the displacement has " + std::to_string(displacement.size()) + " entries, the mesh " +
                   std::to_string(mesh_.dof_count()) + " dofs");
  }
  dispatch(mesh_.element_type, [&](auto kind) {
    using E = decltype(kind);
    using Gradients = Eigen::Matrix<double, E::nodes, E::dimension>;
    constexpr int d = E::dimension;
    out.resize(mesh_.elements.size());
    Eigen::Matrix<double, E::nodes * d, 1> u;
    for (std::size_t e = 0; e < out.size(); ++e) {
      const std::vector<int>& nodes = mesh_.elements[e];
      for (int a = 0; a < E::nodes; ++a) u.template segment<d>(d * a) = displacement.template segment<d>(d * nodes[a]);
      const Gradients dN_dx = Eigen::Map<const Gradients>(gradients_.data() + e * Gradients::SizeAtCompileTime);
      out[e] = centroid_stress<E>(strain_displacement<E::nodes>(dN_dx), u, material_);
    }
  });
}

int nodes_per_face(ElementType type) {
  switch (type) {
    case ElementType::quad4: return 2;
    case ElementType::quad8: return 3;
    case ElementType::hexa8: return 4;
  }
  throw FemError("unknown element type");
}

ElementVector face_pressure_forces(ElementType type, const NodeCoordinates& face_nodes,
                                   double pressure, double thickness, int element) {
  const int n = nodes_per_face(type);
  if (face_nodes.rows() != n) {
    throw FemError("element " + std::to_string(element) + ": a face of a " + to_string(type) +
                   " has " + std::to_string(n) + " nodes, not " +
                   std::to_string(face_nodes.rows()));
  }
  auto degenerate = [&](const Eigen::Vector3d& natural) {
    std::ostringstream message;
    message << "element " << element << ": face of zero length or area at ξ = (" << natural.x()
            << ", " << natural.y() << ")";
    throw FemError(message.str());
  };
  if (type == ElementType::hexa8) {
    // Bilinear face on the quad4 reference square; a = ∂x/∂ξ × ∂x/∂η is the outward normal times
    // the area Jacobian, so f_a = −p Σ_g w_g N_a a.
    ElementVector forces = ElementVector::Zero(12);
    const Eigen::Matrix<double, 4, 3> x = face_nodes;
    for (const GaussPoint& g : gauss_rule(ElementType::quad4)) {
      const Shape<4, 2> s = Quad4::shape(g.natural);
      const Eigen::Matrix<double, 3, 2> tangents = x.transpose() * s.dN;
      const Eigen::Vector3d area = tangents.col(0).cross(tangents.col(1));
      if (!(area.norm() > 0.0)) degenerate(g.natural);
      for (int a = 0; a < 4; ++a) forces.segment<3>(3 * a) -= (pressure * g.weight * s.N(a)) * area;
    }
    return forces;
  }
  // Edge of 2 (linear) or 3 (quadratic: corner at ξ = −1, corner at +1, mid-side at 0) nodes, with
  // the tangent T = ∂x/∂ξ; n ds = (T_y, −T_x) dξ, so f_a = −p t Σ_g w_g N_a (T_y, −T_x).
  if (!(thickness > 0.0) || !std::isfinite(thickness)) {
    std::ostringstream message;
    message << "element " << element << ": thickness = " << thickness << " m must be > 0";
    throw FemError(message.str());
  }
  ElementVector forces = ElementVector::Zero(2 * n);
  for (const GaussPoint& g : gauss_legendre(n)) {
    const double s = g.natural.x();
    Eigen::Vector3d N, dN;  // first n entries used
    if (n == 2) {
      N << 0.5 * (1 - s), 0.5 * (1 + s), 0.0;
      dN << -0.5, 0.5, 0.0;
    } else {
      N << 0.5 * s * (s - 1), 0.5 * s * (s + 1), 1 - s * s;
      dN << s - 0.5, s + 0.5, -2 * s;
    }
    Eigen::Vector2d tangent = Eigen::Vector2d::Zero();
    for (int a = 0; a < n; ++a) tangent += dN(a) * face_nodes.row(a).head<2>().transpose();
    if (!(tangent.norm() > 0.0)) degenerate(g.natural);
    const Eigen::Vector2d normal_length(tangent.y(), -tangent.x());
    for (int a = 0; a < n; ++a)
      forces.segment<2>(2 * a) -= (pressure * thickness * g.weight * N(a)) * normal_length;
  }
  return forces;
}

ElementVector element_values(const Mesh& mesh, int element, const Eigen::VectorXd& values) {
  const int d = mesh.dofs_per_node();
  const std::vector<int>& nodes = mesh.elements[element];
  ElementVector u(static_cast<Eigen::Index>(nodes.size()) * d);
  for (std::size_t a = 0; a < nodes.size(); ++a) u.segment(d * a, d) = values.segment(d * nodes[a], d);
  return u;
}

}  // namespace csim
