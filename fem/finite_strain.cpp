// Element kernels and mesh assembly of finite_strain.h. As in elements.cpp, each kernel is a
// template on the element type so that every matrix has a fixed size; the shape-function
// derivatives at the Gauss points come from elements.h once per type. A kernel makes two passes
// over the Gauss points: the first computes F and J̄ (mean dilatation needs U'(J̄) before any
// tangent is summed), the second the material response, so that the volumetric terms fold into
// one Bᵀ A B per point.
#include "fem/finite_strain.h"

#include "fem/element_dispatch.h"

#include <array>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

namespace csim {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

template <ElementType Type, int Nodes, int Dimension, int Points>
struct Kind {
  static constexpr ElementType type = Type;
  static constexpr int nodes = Nodes, dimension = Dimension, points = Points;
  static constexpr int dofs = Nodes * Dimension, gradient = Dimension * Dimension;
  using Gradients = Eigen::Matrix<double, Nodes, Dimension>;  // row a: ∂N_a/∂ξ or ∂N_a/∂X
  using Nodal = Eigen::Matrix<double, Dimension, Nodes>;      // column a: a vector of node a
  using Square = Eigen::Matrix<double, Dimension, Dimension>;
  using Vector = Eigen::Matrix<double, dofs, 1>;
  using Matrix = Eigen::Matrix<double, dofs, dofs>;
  using Tangent = Eigen::Matrix<double, gradient, gradient>;  // A on the in-plane F_iJ
};
using Quad4 = Kind<ElementType::quad4, 4, 2, 4>;
using Quad8 = Kind<ElementType::quad8, 8, 2, 9>;
using Hexa8 = Kind<ElementType::hexa8, 8, 3, 8>;

template <class Function>
decltype(auto) dispatch(ElementType type, Function&& f) {
  return dispatch_element<Quad4, Quad8, Hexa8>(type, std::forward<Function>(f));
}

// ∂N/∂ξ at the Gauss points of gauss_rule and at the centroid, once per element type.
template <class E>
struct Reference {
  std::array<Eigen::Vector3d, E::points> natural;
  std::array<double, E::points> weight;
  std::array<typename E::Gradients, E::points> derivatives;
  std::array<Eigen::Matrix<double, E::nodes, 1>, E::points> values;  // N_a
  typename E::Gradients centroid;                                     // ∂N_a/∂ξ at ξ = 0
  Eigen::Matrix<double, E::nodes, 1> centre;                          // N_a at ξ = 0
};

template <class E>
const Reference<E>& reference() {
  static const Reference<E> data = [] {
    Reference<E> r;
    const std::vector<GaussPoint> rule = gauss_rule(E::type);
    for (int g = 0; g < E::points; ++g) {
      r.natural[g] = rule[g].natural;
      r.weight[g] = rule[g].weight;
      const ShapeFunctions shape = shape_functions(E::type, rule[g].natural);
      r.derivatives[g] = shape.derivatives.leftCols(E::dimension);
      r.values[g] = shape.values;
    }
    const ShapeFunctions centre = shape_functions(E::type, Eigen::Vector3d::Zero());
    r.centroid = centre.derivatives.leftCols(E::dimension);
    r.centre = centre.values;
    return r;
  }();
  return data;
}

[[noreturn]] void throw_at(int element, const char* what, double value,
                           const Eigen::Vector3d& natural) {
  std::ostringstream message;
  message << "element " << element << what << value << " at ξ = (" << natural.x() << ", "
          << natural.y() << ", " << natural.z() << ")";
  throw FemError(message.str());
}

// The kinematics of one Gauss point.
template <class E>
struct PointKinematics {
  typename E::Gradients gradients;  // ∂N_a/∂X, 1/m
  typename E::Square F;             // deformation gradient; plane strain: its in-plane block
  double J = 1.0;                   // det F
  double volume = 0.0;              // dV, m³
};

// The 3×3 F of a point: a plane element's in-plane block with F33 = 1 and no out-of-plane shear, a
// solid's F itself.
template <class E>
Eigen::Matrix3d whole_gradient(const typename E::Square& F) {
  Eigen::Matrix3d whole = Eigen::Matrix3d::Identity();
  whole.topLeftCorner<E::dimension, E::dimension>() = F;
  return whole;
}

template <class E>
PointKinematics<E> kinematics(const typename E::Gradients& X, const typename E::Nodal& u,
                              const typename E::Gradients& derivatives, double weight, double scale,
                              int element, const Eigen::Vector3d& natural) {
  PointKinematics<E> p;
  const typename E::Square jacobian = X.transpose() * derivatives;
  const double det = jacobian.determinant();
  if (!(det > 0.0) || !std::isfinite(det))
    throw_at(element, " has a non-positive Jacobian (inverted or degenerate): det J = ", det,
             natural);
  p.gradients.noalias() = derivatives * jacobian.inverse();
  p.F.setIdentity();
  p.F += u * p.gradients;
  p.J = p.F.determinant();
  if (!(p.J > 0.0) || !std::isfinite(p.J))
    throw_at(element, " is inverted: det F = ", p.J, natural);
  p.volume = weight * det * scale;
  return p;
}

// B, with B(D·i + J, D·b + k) = δik ∂N_b/∂X_J so that vec(F − I) = B u_e (in-plane F_iJ only), is
// never formed: its products go node by node through g_b = ∂N_b/∂X. As dense matrices they went
// through Eigen's general matrix product (24 × 9 × 24 for hexa8), a fifth of a 3D ring's run.

// Bᵀ v (dofs) of a vector v over F's entries: (Bᵀ v)(D·b + i) = Σ_J g_bJ v(D·i + J).
template <class E>
typename E::Vector gradient_transpose_times(const typename E::Gradients& g,
                                            const Eigen::Matrix<double, E::gradient, 1>& v) {
  constexpr int D = E::dimension;
  typename E::Vector result;
  for (int b = 0; b < E::nodes; ++b)
    for (int i = 0; i < D; ++i)
      result(D * b + i) = g.row(b).dot(v.template segment<D>(D * i));
  return result;
}

// K += dV Bᵀ A B, that is K(D·a + i, D·b + k) += dV Σ_J g_aJ A(D·i + J, D·k + L) g_bL:
// A B first (its column D·b + k is A's columns D·k … D·k + D − 1 times g_b), with its rows in the
// order D·J + i, then Bᵀ (A B) column by column, so that both are read and written contiguously
// (row by row, with K column-major, took a fifth of a 3D ring's run). Each entry of K gets the same
// products in the same order (J = 0 … D − 1) as row by row: the same result bit for bit. K is
// symmetric: only its node blocks on and above the diagonal (a ≤ b) are summed here, and
// evaluate_with mirrors the upper triangle once all terms are in.
template <class E>
void add_material_stiffness(const typename E::Gradients& g, const typename E::Tangent& A, double dV,
                            typename E::Matrix& K) {
  constexpr int D = E::dimension;
  typename E::Tangent A_by_J;  // A's rows in the order D·J + i
  for (int i = 0; i < D; ++i)
    for (int J = 0; J < D; ++J) A_by_J.row(D * J + i) = A.row(D * i + J);
  Eigen::Matrix<double, E::gradient, E::dofs> AB;
  for (int b = 0; b < E::nodes; ++b)
    for (int k = 0; k < D; ++k)
      AB.col(D * b + k).noalias() = A_by_J.template middleCols<D>(D * k) * g.row(b).transpose();
  const typename E::Gradients weighted = dV * g;
  for (int b = 0; b < E::nodes; ++b)
    for (int k = 0; k < D; ++k) {
      auto column = K.col(D * b + k);
      const auto products = AB.col(D * b + k);
      for (int a = 0; a <= b; ++a)
        for (int J = 0; J < D; ++J)
          column.template segment<D>(D * a) += weighted(a, J) * products.template segment<D>(D * J);
    }
}

struct KernelInput {
  const HyperelasticMaterial& material;
  FiniteStrainFormulation formulation;
  double scale;  // thickness for plane elements, 1 for solids
  int element;
};

template <class E>
struct KernelOutput {
  double energy = 0.0;
  typename E::Vector force;
  typename E::Matrix tangent;
};

// The element's dilatation field θ(X) = φ(X)·c, the L² projection of J onto the span of φ:
// φ = 1 (mean dilatation, Modes = 1) or φ = (1, (X − X̄)/ℓ) (linear dilatation, Modes = D + 1),
// X the reference position, X̄ the element's centroid and ℓ = (V_e/scale)^(1/D) its size (which
// keeps the projection's matrix near the identity). With M = ∫ φ φᵀ dV:
//   c = M⁻¹ ∫ φ J dV,  Π_vol = ∫ U(θ) dV,  pressure p(X) = φ(X)·p̂, p̂ = M⁻¹ ∫ U'(θ) φ dV,
//   f_vol = ∫ p Bᵀ ∂J/∂F dV = G p̂ with G = ∫ Bᵀ ∂J/∂F φᵀ dV,
//   K_vol = G M⁻¹ (∫ U''(θ) φ φᵀ dV) M⁻¹ Gᵀ + ∫ p Bᵀ (∂²J/∂F∂F) B dV.
// With Modes = 1 this is θ = J̄, p = U'(J̄) and K_vol's first term U''(J̄)/V_e g gᵀ (finite_strain.h).
template <int Points, int Modes>
struct Dilatation {
  using Basis = Eigen::Matrix<double, Modes, 1>;
  using Gram = Eigen::Matrix<double, Modes, Modes>;
  std::array<Basis, Points> basis;  // φ at the Gauss points
  double energy = 0.0;              // Π_vol, J
  Basis pressure;                   // p̂, Pa
  Gram inverse_gram;                // M⁻¹, 1/m³
  Gram stiffness;                   // ∫ U''(θ) φ φᵀ dV, J
};

// φ at the reference position x (m) of an element with centroid X̄ and size ℓ.
template <int Modes, class Point>
Eigen::Matrix<double, Modes, 1> dilatation_basis(const Point& x, const Point& centroid,
                                                 double size) {
  Eigen::Matrix<double, Modes, 1> phi;
  phi(0) = 1.0;
  if constexpr (Modes > 1) phi.template tail<Modes - 1>() = (x - centroid) / size;
  return phi;
}

template <class E>
struct ElementPoints {
  std::array<PointKinematics<E>, E::points> kinematics;
  std::array<Eigen::Matrix<double, E::dimension, 1>, E::points> position;  // X at the point, m
  Eigen::Matrix<double, E::dimension, 1> centroid;                         // X̄, m
  double volume = 0.0;                                                     // V_e, m³
  double size = 1.0;                                                       // ℓ, m
};

// The positions, centroid and size only for a dilatation of more than one mode (the only reader of
// them: dilatation_basis), so that the standard and mean-dilatation kernels skip them and their pow.
template <class E, int Modes>
ElementPoints<E> element_points(const typename E::Gradients& X, const typename E::Nodal& u,
                                const KernelInput& in) {
  constexpr bool positions = Modes > 1;
  const Reference<E>& ref = reference<E>();
  ElementPoints<E> points;
  points.centroid.setZero();
  for (int g = 0; g < E::points; ++g) {
    points.kinematics[g] = kinematics<E>(X, u, ref.derivatives[g], ref.weight[g], in.scale,
                                         in.element, ref.natural[g]);
    points.volume += points.kinematics[g].volume;
    if constexpr (positions) {
      points.position[g] = X.transpose() * ref.values[g];
      points.centroid += points.kinematics[g].volume * points.position[g];
    }
  }
  if constexpr (positions) {
    points.centroid /= points.volume;
    points.size = std::pow(points.volume / in.scale, 1.0 / E::dimension);
  }
  return points;
}

template <class E, int Modes>
Dilatation<E::points, Modes> project_dilatation(const ElementPoints<E>& points, const KernelInput& in) {
  const Reference<E>& ref = reference<E>();
  using D = Dilatation<E::points, Modes>;
  D d;
  typename D::Gram gram = D::Gram::Zero();
  typename D::Basis volume_change = D::Basis::Zero();
  std::array<typename D::Basis, E::points>& phi = d.basis;
  for (int g = 0; g < E::points; ++g) {
    const PointKinematics<E>& p = points.kinematics[g];
    phi[g] = dilatation_basis<Modes>(points.position[g], points.centroid, points.size);
    gram.noalias() += p.volume * phi[g] * phi[g].transpose();
    volume_change += p.volume * p.J * phi[g];
  }
  d.inverse_gram = gram.inverse();
  const typename D::Basis c = d.inverse_gram * volume_change;
  typename D::Basis mean_stress = D::Basis::Zero();
  d.stiffness.setZero();
  VolumetricResponse v;
  for (int g = 0; g < E::points; ++g) {
    // One mode (φ = 1): θ = J̄ at every point, so U and its derivatives are evaluated once.
    if (Modes > 1 || g == 0) {
      const double theta = phi[g].dot(c);
      if (!(theta > 0.0) || !std::isfinite(theta))
        throw_at(in.element, " is inverted: its projected volume ratio θ = ", theta, ref.natural[g]);
      v = volumetric_response(in.material, theta);
    }
    const double dV = points.kinematics[g].volume;
    d.energy += dV * v.energy;
    mean_stress += dV * v.mean_stress * phi[g];
    d.stiffness.noalias() += dV * v.stiffness * phi[g] * phi[g].transpose();
  }
  d.pressure = d.inverse_gram * mean_stress;
  return d;
}

// ∂J/∂F = J H, H = F⁻ᵀ: the cofactor matrix of F, which in plane strain is [[F22, −F21], [−F12, F11]]
// (no inverse needed).
template <class E>
typename E::Square volume_derivative(const typename E::Square& F, double det_F) {
  if constexpr (E::dimension == 2) {
    typename E::Square cofactor;
    cofactor << F(1, 1), -F(1, 0), -F(0, 1), F(0, 0);
    return cofactor;
  } else {
    return det_F * F.inverse().transpose();
  }
}

// A += p ∂²J/∂F∂F, ∂²J/∂F_iJ∂F_kL = J (H_iJ H_kL − H_iL H_kJ). In plane strain J = F11 F22 − F12 F21
// is bilinear: its Hessian is the constant ±1 on the pairs (F11, F22) and (F12, F21).
template <class E>
void add_volume_hessian(typename E::Tangent& A, double pressure, const typename E::Square& F,
                        double det_F) {
  constexpr int D = E::dimension;
  if constexpr (D == 2) {
    A(0, 3) += pressure, A(3, 0) += pressure;
    A(1, 2) -= pressure, A(2, 1) -= pressure;
  } else {
    const typename E::Square H = F.inverse().transpose();
    for (int i = 0; i < D; ++i)
      for (int J = 0; J < D; ++J)
        for (int k = 0; k < D; ++k)
          for (int L = 0; L < D; ++L)
            A(D * i + J, D * k + L) += pressure * det_F * (H(i, J) * H(k, L) - H(i, L) * H(k, J));
  }
}

// X's entries row by row, the order of A's rows and columns.
template <class E>
Eigen::Matrix<double, E::gradient, 1> by_rows(const typename E::Square& X) {
  Eigen::Matrix<double, E::gradient, 1> flat;
  for (int i = 0; i < E::dimension; ++i)
    for (int J = 0; J < E::dimension; ++J) flat(E::dimension * i + J) = X(i, J);
  return flat;
}

// Modes = 0: the standard element; otherwise W_iso at the points and U on the projected
// dilatation of Modes modes.
template <class E, int Modes>
void evaluate_with(const typename E::Gradients& X, const typename E::Nodal& u,
                   const KernelInput& in, bool with_tangent, KernelOutput<E>& out) {
  constexpr int D = E::dimension;
  constexpr bool split = Modes > 0;
  constexpr int M = split ? Modes : 1;
  const ElementPoints<E> points = element_points<E, Modes>(X, u, in);
  Dilatation<E::points, M> dilatation;
  if constexpr (split) dilatation = project_dilatation<E, M>(points, in);

  Eigen::Matrix<double, D, E::nodes> force = Eigen::Matrix<double, D, E::nodes>::Zero();
  Eigen::Matrix<double, E::dofs, M> volume_gradient;  // G, m³ per m and mode
  volume_gradient.setZero();
  out.energy = dilatation.energy;
  if (with_tangent) out.tangent.setZero();
  for (int g = 0; g < E::points; ++g) {
    const PointKinematics<E>& p = points.kinematics[g];
    HyperelasticResponseOf<D> response =
        split ? isochoric_response<D>(in.material, p.F, with_tangent)
              : hyperelastic_response<D>(in.material, p.F, with_tangent);
    typename E::Square& P = response.stress;    // the in-plane (or whole) block
    typename E::Tangent& A = response.tangent;  // the in-plane (or whole) block
    if constexpr (split) {
      // The pressure's share: p ∂J/∂F in P, p ∂²J/∂F∂F in A, ∂J/∂F in the volume gradient G.
      const Eigen::Matrix<double, M, 1>& phi = dilatation.basis[g];
      const double pressure = phi.dot(dilatation.pressure);
      const typename E::Square dJ = volume_derivative<E>(p.F, p.J);
      P += pressure * dJ;
      if (with_tangent) {
        add_volume_hessian<E>(A, pressure, p.F, p.J);
        volume_gradient.noalias() +=
            p.volume * (gradient_transpose_times<E>(p.gradients, by_rows<E>(dJ)) * phi.transpose());
      }
    }
    out.energy += p.volume * response.energy;
    force.noalias() += p.volume * (P * p.gradients.transpose());
    if (with_tangent) add_material_stiffness<E>(p.gradients, A, p.volume, out.tangent);
  }
  out.force = Eigen::Map<const typename E::Vector>(force.data());
  if (!with_tangent) return;
  if constexpr (split) {
    const Eigen::Matrix<double, M, M> volumetric =
        dilatation.inverse_gram * dilatation.stiffness * dilatation.inverse_gram;
    out.tangent.noalias() += volume_gradient * (volumetric * volume_gradient.transpose());
  }
  // Exactly symmetric, as symmetric factorizations assume: the upper triangle, on which
  // add_material_stiffness summed, mirrored into the lower.
  for (int c = 0; c < E::dofs; ++c)
    for (int r = c + 1; r < E::dofs; ++r) out.tangent(r, c) = out.tangent(c, r);
}

template <class E>
void evaluate(const typename E::Gradients& X, const typename E::Nodal& u, const KernelInput& in,
              bool with_tangent, KernelOutput<E>& out) {
  switch (in.formulation) {
    case FiniteStrainFormulation::standard: return evaluate_with<E, 0>(X, u, in, with_tangent, out);
    case FiniteStrainFormulation::mean_dilatation:
      return evaluate_with<E, 1>(X, u, in, with_tangent, out);
    case FiniteStrainFormulation::linear_dilatation:
      return evaluate_with<E, E::dimension + 1>(X, u, in, with_tangent, out);
  }
}

// The volumetric part of the centroid stress: U'(J) at the point, or the projected pressure.
template <class E, int Modes>
double centroid_pressure(const typename E::Gradients& X, const typename E::Nodal& u,
                         const KernelInput& in) {
  const ElementPoints<E> points = element_points<E, Modes>(X, u, in);
  const Dilatation<E::points, Modes> d = project_dilatation<E, Modes>(points, in);
  const Eigen::Matrix<double, E::dimension, 1> centre = X.transpose() * reference<E>().centre;
  return dilatation_basis<Modes>(centre, points.centroid, points.size).dot(d.pressure);
}

template <class E>
Stress centroid_stress(const typename E::Gradients& X, const typename E::Nodal& u,
                       const KernelInput& in) {
  const Reference<E>& ref = reference<E>();
  const PointKinematics<E> centre =
      kinematics<E>(X, u, ref.centroid, 1.0, 1.0, in.element, Eigen::Vector3d::Zero());
  const Eigen::Matrix3d F = whole_gradient<E>(centre.F);  // the 3D response, for σzz
  Eigen::Matrix3d sigma;
  if (in.formulation == FiniteStrainFormulation::standard) {
    const HyperelasticResponse r = hyperelastic_response(in.material, F, false);
    sigma = r.stress * F.transpose() / centre.J;
  } else {
    const double pressure = in.formulation == FiniteStrainFormulation::mean_dilatation
                                ? centroid_pressure<E, 1>(X, u, in)
                                : centroid_pressure<E, E::dimension + 1>(X, u, in);
    const HyperelasticResponse r = isochoric_response(in.material, F, false);
    sigma = r.stress * F.transpose() / centre.J + pressure * Eigen::Matrix3d::Identity();
  }
  Stress stress;
  stress << sigma(0, 0), sigma(1, 1), sigma(2, 2), sigma(0, 1), sigma(1, 2), sigma(0, 2);
  return stress;
}

double checked_scale(ElementType type, double thickness, int element) {
  if (mesh_dimension(type) == 3) return 1.0;
  if (!(thickness > 0.0) || !std::isfinite(thickness)) {
    std::ostringstream message;
    message << "element " << element << ": thickness = " << thickness << " m must be > 0";
    throw FemError(message.str());
  }
  return thickness;
}

// element < 0: a mesh-wide quantity. The message is built only on failure: this runs per element
// inside the assembly loop, which must not allocate.
void check_size(int element, const char* what, Eigen::Index size, Eigen::Index expected) {
  if (size != expected) {
    const std::string owner = element >= 0 ? "element " + std::to_string(element) + ": " : "";
    throw FemError(owner + what + " has " + std::to_string(size) + " entries, expected " +
                   std::to_string(expected));
  }
}

template <class E>
typename E::Gradients reference_coordinates(const ElementGeometry& element) {
  check_size(element.index, "the node coordinates", element.coordinates.rows(), E::nodes);
  return element.coordinates.template leftCols<E::dimension>();
}

// Gathers, evaluates and scatters every element: into energy always, force and triplets if given.
double assemble(const FiniteStrainModel& model, const Eigen::VectorXd& displacement,
                Eigen::VectorXd* force, Triplets* triplets, const DofNumbering* numbering = nullptr) {
  const Mesh& mesh = model.mesh;
  check_hyperelastic(model.material);
  check_size(-1, "the displacement", displacement.size(), mesh.dof_count());
  if (mesh.dimension() == 2 && (!(model.thickness > 0.0) || !std::isfinite(model.thickness))) {
    std::ostringstream message;
    message << "thickness = " << model.thickness << " m must be > 0 for a plane-strain mesh";
    throw FemError(message.str());
  }
  check_formulation(mesh.element_type, model.formulation);
  const double scale = mesh.dimension() == 2 ? model.thickness : 1.0;
  if (force) force->setZero(mesh.dof_count());
  if (triplets && !numbering) triplets->clear();
  return dispatch(mesh.element_type, [&](auto kind) {
    using E = decltype(kind);
    constexpr int D = E::dimension;
    const int element_count = static_cast<int>(mesh.elements.size());
    if (triplets) triplets->reserve(triplets->size() + static_cast<std::size_t>(element_count) * E::dofs * E::dofs);
    std::array<int, E::dofs> kept, numbered;  // the element's unfixed dofs and their numbers
    double energy = 0.0;
    KernelOutput<E> out;
    std::array<int, E::dofs> dofs;
    for (int e = 0; e < element_count; ++e) {
      const ElementGeometry geometry = element_geometry(mesh, e);
      typename E::Nodal u;
      for (int a = 0; a < E::nodes; ++a)
        for (int i = 0; i < D; ++i) {
          dofs[D * a + i] = D * mesh.elements[e][a] + i;
          u(i, a) = displacement(dofs[D * a + i]);
        }
      evaluate<E>(reference_coordinates<E>(geometry), u,
                  {model.material, model.formulation, scale, e}, triplets != nullptr, out);
      energy += out.energy;
      if (force)
        for (int r = 0; r < E::dofs; ++r) (*force)(dofs[r]) += out.force(r);
      if (triplets && !numbering)
        for (int c = 0; c < E::dofs; ++c)
          for (int r = 0; r < E::dofs; ++r)
            triplets->emplace_back(dofs[r], dofs[c], out.tangent(r, c));
      if (triplets && numbering) {
        // The unfixed dofs listed once, so that the E::dofs² entries need no test each.
        int count = 0;
        for (int r = 0; r < E::dofs; ++r)
          if (const int n = numbering->numbering[dofs[r]]; n >= 0)
            kept[count] = r, numbered[count++] = numbering->offset + n;
        for (int c = 0; c < count; ++c)
          for (int r = 0; r < count; ++r)
            triplets->emplace_back(numbered[r], numbered[c], out.tangent(kept[r], kept[c]));
      }
    }
    return energy;
  });
}

}  // namespace

const char* to_string(FiniteStrainFormulation formulation) {
  switch (formulation) {
    case FiniteStrainFormulation::standard: return "standard";
    case FiniteStrainFormulation::mean_dilatation: return "mean_dilatation";
    case FiniteStrainFormulation::linear_dilatation: return "linear_dilatation";
  }
  return "unknown";
}

// A linear dilatation constrains D + 1 modes per element: more than quad4 and hexa8 have
// displacement modes per element on a large mesh (about D), so they would lock.
void check_formulation(ElementType type, FiniteStrainFormulation formulation) {
  if (formulation == FiniteStrainFormulation::linear_dilatation && type != ElementType::quad8)
    throw FemError(std::string("a linear dilatation (Q2/P1) needs quad8 elements, not ") + to_string(type) +
                   " (a linear pressure locks a linear element; a mean dilatation does not)");
}

FiniteStrainElementResult finite_strain_element(const ElementGeometry& element,
                                                const HyperelasticMaterial& material,
                                                double thickness,
                                                FiniteStrainFormulation formulation,
                                                const ElementVector& displacement,
                                                FiniteStrainOutput output) {
  check_hyperelastic(material);
  check_formulation(element.type, formulation);
  const double scale = checked_scale(element.type, thickness, element.index);
  return dispatch(element.type, [&](auto kind) {
    using E = decltype(kind);
    check_size(element.index, "the displacement", displacement.size(), E::dofs);
    const typename E::Nodal u = Eigen::Map<const typename E::Nodal>(displacement.data());
    const bool with_tangent = output == FiniteStrainOutput::energy_force_and_tangent;
    KernelOutput<E> out;
    evaluate<E>(reference_coordinates<E>(element), u, {material, formulation, scale, element.index},
                with_tangent, out);
    FiniteStrainElementResult result;
    result.energy = out.energy;
    result.force = out.force;
    if (with_tangent) result.tangent = out.tangent;
    return result;
  });
}

Stress finite_strain_centroid_stress(const ElementGeometry& element,
                                     const HyperelasticMaterial& material,
                                     FiniteStrainFormulation formulation,
                                     const ElementVector& displacement) {
  check_hyperelastic(material);
  check_formulation(element.type, formulation);
  return dispatch(element.type, [&](auto kind) {
    using E = decltype(kind);
    check_size(element.index, "the displacement", displacement.size(), E::dofs);
    const typename E::Nodal u = Eigen::Map<const typename E::Nodal>(displacement.data());
    return centroid_stress<E>(reference_coordinates<E>(element), u,
                              {material, formulation, 1.0, element.index});
  });
}

Eigen::Matrix3d finite_strain_centroid_gradient(const ElementGeometry& element,
                                                const ElementVector& displacement) {
  return dispatch(element.type, [&](auto kind) -> Eigen::Matrix3d {
    using E = decltype(kind);
    check_size(element.index, "the displacement", displacement.size(), E::dofs);
    const typename E::Nodal u = Eigen::Map<const typename E::Nodal>(displacement.data());
    return whole_gradient<E>(kinematics<E>(reference_coordinates<E>(element), u,
                                           reference<E>().centroid, 1.0, 1.0, element.index,
                                           Eigen::Vector3d::Zero())
                                 .F);
  });
}

double strain_energy(const FiniteStrainModel& model, const Eigen::VectorXd& displacement) {
  return assemble(model, displacement, nullptr, nullptr);
}

double internal_force(const FiniteStrainModel& model, const Eigen::VectorXd& displacement,
                      Eigen::VectorXd& force) {
  return assemble(model, displacement, &force, nullptr);
}

void tangent_triplets(const FiniteStrainModel& model, const Eigen::VectorXd& displacement,
                      Triplets& triplets) {
  assemble(model, displacement, nullptr, &triplets);
}

double assemble_finite_strain(const FiniteStrainModel& model, const Eigen::VectorXd& displacement,
                              Eigen::VectorXd& force, Triplets& triplets) {
  return assemble(model, displacement, &force, &triplets);
}

double assemble_finite_strain(const FiniteStrainModel& model, const Eigen::VectorXd& displacement,
                              Eigen::VectorXd& force, const DofNumbering& numbering, Triplets& triplets) {
  check_size(-1, "the dof numbering", static_cast<Eigen::Index>(numbering.numbering.size()), model.mesh.dof_count());
  return assemble(model, displacement, &force, &triplets, &numbering);
}

std::vector<Stress> cauchy_stresses(const FiniteStrainModel& model,
                                    const Eigen::VectorXd& displacement) {
  const Mesh& mesh = model.mesh;
  check_size(-1, "the displacement", displacement.size(), mesh.dof_count());
  std::vector<Stress> stresses;
  stresses.reserve(mesh.elements.size());
  for (int e = 0; e < static_cast<int>(mesh.elements.size()); ++e) {
    const ElementGeometry geometry = element_geometry(mesh, e);
    const ElementVector u = element_values(mesh, e, displacement);
    stresses.push_back(
        finite_strain_centroid_stress(geometry, model.material, model.formulation, u));
  }
  return stresses;
}

std::vector<Eigen::Matrix3d> centroid_gradients(const Mesh& mesh, const Eigen::VectorXd& displacement) {
  check_size(-1, "the displacement", displacement.size(), mesh.dof_count());
  std::vector<Eigen::Matrix3d> gradients;
  gradients.reserve(mesh.elements.size());
  for (int e = 0; e < static_cast<int>(mesh.elements.size()); ++e)
    gradients.push_back(finite_strain_centroid_gradient(element_geometry(mesh, e),
                                                        element_values(mesh, e, displacement)));
  return gradients;
}

}  // namespace csim
