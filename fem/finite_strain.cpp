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
  using GradientMap = Eigen::Matrix<double, gradient, dofs>;  // B: u_e → F, row D·i + J
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
  typename E::Gradients centroid;
};

template <class E>
const Reference<E>& reference() {
  static const Reference<E> data = [] {
    Reference<E> r;
    const std::vector<GaussPoint> rule = gauss_rule(E::type);
    for (int g = 0; g < E::points; ++g) {
      r.natural[g] = rule[g].natural;
      r.weight[g] = rule[g].weight;
      r.derivatives[g] =
          shape_functions(E::type, rule[g].natural).derivatives.leftCols(E::dimension);
    }
    r.centroid =
        shape_functions(E::type, Eigen::Vector3d::Zero()).derivatives.leftCols(E::dimension);
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
  Eigen::Matrix3d F;                // deformation gradient, plane strain F33 = 1
  double J = 1.0;                   // det F
  double volume = 0.0;              // dV, m³
};

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
  p.F.template topLeftCorner<E::dimension, E::dimension>() += u * p.gradients;
  p.J = p.F.determinant();
  if (!(p.J > 0.0) || !std::isfinite(p.J))
    throw_at(element, " is inverted: det F = ", p.J, natural);
  p.volume = weight * det * scale;
  return p;
}

// B with B(D·i + J, D·b + k) = δik ∂N_b/∂X_J, so that vec(F − I) = B u_e (in-plane F_iJ only).
template <class E>
typename E::GradientMap gradient_map(const typename E::Gradients& gradients) {
  typename E::GradientMap B = E::GradientMap::Zero();
  for (int b = 0; b < E::nodes; ++b)
    for (int i = 0; i < E::dimension; ++i)
      for (int J = 0; J < E::dimension; ++J)
        B(E::dimension * i + J, E::dimension * b + i) = gradients(b, J);
  return B;
}

// The in-plane (or full) block of a 9×9 material tangent.
template <class E>
typename E::Tangent restrict_tangent(const MaterialTangent& A) {
  typename E::Tangent block;
  constexpr int D = E::dimension;
  for (int i = 0; i < D; ++i)
    for (int J = 0; J < D; ++J)
      for (int k = 0; k < D; ++k)
        for (int L = 0; L < D; ++L) block(D * i + J, D * k + L) = A(3 * i + J, 3 * k + L);
  return block;
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

template <class E>
void evaluate(const typename E::Gradients& X, const typename E::Nodal& u, const KernelInput& in,
              bool with_tangent, KernelOutput<E>& out) {
  constexpr int D = E::dimension;
  const Reference<E>& ref = reference<E>();
  std::array<PointKinematics<E>, E::points> points;
  double current_volume = 0.0, reference_volume = 0.0;
  for (int g = 0; g < E::points; ++g) {
    points[g] = kinematics<E>(X, u, ref.derivatives[g], ref.weight[g], in.scale, in.element,
                              ref.natural[g]);
    current_volume += points[g].J * points[g].volume;
    reference_volume += points[g].volume;
  }
  const bool mean_dilatation = in.formulation == FiniteStrainFormulation::mean_dilatation;
  VolumetricResponse volumetric;
  if (mean_dilatation)
    volumetric = volumetric_response(in.material, current_volume / reference_volume);

  Eigen::Matrix<double, D, E::nodes> force = Eigen::Matrix<double, D, E::nodes>::Zero();
  typename E::Vector volume_gradient = E::Vector::Zero();  // g = ∂v_e/∂u_e, m²
  out.energy = mean_dilatation ? reference_volume * volumetric.energy : 0.0;
  if (with_tangent) out.tangent.setZero();
  for (const PointKinematics<E>& p : points) {
    HyperelasticResponse response = mean_dilatation
                                        ? isochoric_response(in.material, p.F, with_tangent)
                                        : hyperelastic_response(in.material, p.F, with_tangent);
    typename E::Square P = response.stress.template topLeftCorner<D, D>();
    typename E::Tangent A;
    typename E::GradientMap B;
    if (with_tangent) {
      A = restrict_tangent<E>(response.tangent);
      B = gradient_map<E>(p.gradients);
    }
    if (mean_dilatation) {
      // U'(J̄) ∂J/∂F and U'(J̄) ∂²J/∂F∂F, ∂J/∂F = J H, ∂²J/∂F_iJ∂F_kL = J (H_iJ H_kL − H_iL H_kJ).
      const typename E::Square H = p.F.template topLeftCorner<D, D>().inverse().transpose();
      P += volumetric.mean_stress * p.J * H;
      if (with_tangent) {
        Eigen::Matrix<double, E::gradient, 1> dJ;
        for (int i = 0; i < D; ++i)
          for (int J = 0; J < D; ++J) {
            dJ(D * i + J) = p.J * H(i, J);
            for (int k = 0; k < D; ++k)
              for (int L = 0; L < D; ++L)
                A(D * i + J, D * k + L) +=
                    volumetric.mean_stress * p.J * (H(i, J) * H(k, L) - H(i, L) * H(k, J));
          }
        volume_gradient.noalias() += p.volume * (B.transpose() * dJ);
      }
    }
    out.energy += p.volume * response.energy;
    force.noalias() += p.volume * (P * p.gradients.transpose());
    if (with_tangent) out.tangent.noalias() += p.volume * (B.transpose() * (A * B));
  }
  out.force = Eigen::Map<const typename E::Vector>(force.data());
  if (!with_tangent) return;
  if (mean_dilatation)
    out.tangent.noalias() +=
        (volumetric.stiffness / reference_volume) * (volume_gradient * volume_gradient.transpose());
  // Exactly symmetric (round-off in Bᵀ(AB) is not), as symmetric factorizations assume.
  out.tangent = 0.5 * (out.tangent + out.tangent.transpose()).eval();
}

template <class E>
Stress centroid_stress(const typename E::Gradients& X, const typename E::Nodal& u,
                       const KernelInput& in) {
  const Reference<E>& ref = reference<E>();
  const PointKinematics<E> centre =
      kinematics<E>(X, u, ref.centroid, 1.0, 1.0, in.element, Eigen::Vector3d::Zero());
  Eigen::Matrix3d sigma;
  if (in.formulation == FiniteStrainFormulation::mean_dilatation) {
    double current_volume = 0.0, reference_volume = 0.0;
    for (int g = 0; g < E::points; ++g) {
      const PointKinematics<E> p =
          kinematics<E>(X, u, ref.derivatives[g], ref.weight[g], 1.0, in.element, ref.natural[g]);
      current_volume += p.J * p.volume;
      reference_volume += p.volume;
    }
    const double mean_stress =
        volumetric_response(in.material, current_volume / reference_volume).mean_stress;
    const HyperelasticResponse r = isochoric_response(in.material, centre.F, false);
    sigma = r.stress * centre.F.transpose() / centre.J + mean_stress * Eigen::Matrix3d::Identity();
  } else {
    const HyperelasticResponse r = hyperelastic_response(in.material, centre.F, false);
    sigma = r.stress * centre.F.transpose() / centre.J;
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
                Eigen::VectorXd* force, Triplets* triplets) {
  const Mesh& mesh = model.mesh;
  check_hyperelastic(model.material);
  check_size(-1, "the displacement", displacement.size(), mesh.dof_count());
  if (mesh.dimension() == 2 && (!(model.thickness > 0.0) || !std::isfinite(model.thickness))) {
    std::ostringstream message;
    message << "thickness = " << model.thickness << " m must be > 0 for a plane-strain mesh";
    throw FemError(message.str());
  }
  const double scale = mesh.dimension() == 2 ? model.thickness : 1.0;
  if (force) force->setZero(mesh.dof_count());
  if (triplets) triplets->clear();
  return dispatch(mesh.element_type, [&](auto kind) {
    using E = decltype(kind);
    constexpr int D = E::dimension;
    const int element_count = static_cast<int>(mesh.elements.size());
    if (triplets) triplets->reserve(static_cast<std::size_t>(element_count) * E::dofs * E::dofs);
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
      if (triplets)
        for (int c = 0; c < E::dofs; ++c)
          for (int r = 0; r < E::dofs; ++r)
            triplets->emplace_back(dofs[r], dofs[c], out.tangent(r, c));
    }
    return energy;
  });
}

}  // namespace

const char* to_string(FiniteStrainFormulation formulation) {
  switch (formulation) {
    case FiniteStrainFormulation::standard: return "standard";
    case FiniteStrainFormulation::mean_dilatation: return "mean_dilatation";
  }
  return "unknown";
}

FiniteStrainElementResult finite_strain_element(const ElementGeometry& element,
                                                const HyperelasticMaterial& material,
                                                double thickness,
                                                FiniteStrainFormulation formulation,
                                                const ElementVector& displacement,
                                                FiniteStrainOutput output) {
  check_hyperelastic(material);
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
  return dispatch(element.type, [&](auto kind) {
    using E = decltype(kind);
    check_size(element.index, "the displacement", displacement.size(), E::dofs);
    const typename E::Nodal u = Eigen::Map<const typename E::Nodal>(displacement.data());
    return centroid_stress<E>(reference_coordinates<E>(element), u,
                              {material, formulation, 1.0, element.index});
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

}  // namespace csim
