// The stress (and, for finite strain, the strain) that the output shows for an elastic body: one value
// per element, at its centroid ξ = 0, from the body's own law on the current configuration x = X + u.
//
//   linear body         σ = λ tr ε I + 2μ ε (fem/material.h) of the small strain ε = sym ∇u
//                       (fem/elements.h's element_centroid_stress). Right for small displacements and
//                       small rotations only: a rigid rotation by θ shows as a stress of order E θ².
//   finite-strain body  σ = J⁻¹ P Fᵀ, the Cauchy stress of its hyperelastic law (fem/hyperelastic.h)
//                       at the centroid's F (fem/finite_strain.h's finite_strain_centroid_stress; the
//                       mean- and linear-dilatation elements take its volumetric part from the element's
//                       pressure, the one their energy uses); rigid motions are stress-free whatever
//                       the rotation. Strain: Green–Lagrange E = ½(FᵀF − I) at the same point.
//
// Units and signs: σ in Pa, tension positive, on the current configuration (force per current area);
// E dimensionless, tensor components (E_xy, not the engineering 2 E_xy). Both as fem's Stress, in VTK's
// symmetric-tensor order (xx, yy, zz, xy, yz, xz). Plane strain: σzz is the stress that holds the
// thickness, ν(σxx + σyy) for the linear law and the law's own σzz at F33 = 1 for finite strain;
// Ezz = 0.
//
// Why the centroid, and one value per element, for both kinds (the writer's choice before finite
// strain got its own law): the mixed elements' pressure is one per element (Q1/P0), and the centroid
// is the bilinear element's optimal stress point (Barlow, IJNME 10, 1976, 243–251). Averaging to
// nodes would blend the jumps between elements into their neighbours; ParaView's "Cell Data to Point
// Data" does it on demand.
#pragma once

#include "engine/bodies/fe_body.h"
#include "fem/elements.h"

#include <Eigen/Dense>
#include <optional>
#include <string>
#include <vector>

namespace csim {

struct ElementFields {
  std::vector<Stress> stress;  // σ, Pa, one per element
  std::vector<Stress> strain;  // E, dimensionless, one per element; empty for a linear body
  // Which stress and which strain these are, in ASCII words for the output file's header.
  std::string stress_description, strain_description;
};

// The fields of `body` at the displacement of all its mesh dofs (m, node-major as
// FeBody::full_displacement). Throws FemError from fem/ (a size mismatch, an inverted element: no
// finite-strain law has a stress for det F ≤ 0).
ElementFields element_fields(const FeBody& body, const Eigen::VectorXd& displacement);

// element_fields of one body, frame after frame: a linear body's stresses through a CentroidStressMap
// (fem/elements.h) formed at the first frame, not at each as element_fields does (the same bits at a
// quarter of the cost); a finite-strain body's as element_fields. The body must outlive it.
class ElementFieldsSeries {
 public:
  explicit ElementFieldsSeries(const FeBody& body) : body_(body) {}
  ElementFields operator()(const Eigen::VectorXd& displacement);

 private:
  const FeBody& body_;
  std::optional<CentroidStressMap> linear_stresses_;
};

}  // namespace csim
