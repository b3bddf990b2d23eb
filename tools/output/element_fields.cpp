#include "tools/output/element_fields.h"

#include "fem/assembly.h"
#include "fem/finite_strain.h"

namespace csim {

namespace {

Stress green_lagrange(const Eigen::Matrix3d& F) {
  const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
  Stress strain;
  strain << E(0, 0), E(1, 1), E(2, 2), E(0, 1), E(1, 2), E(0, 2);
  return strain;
}

const char* const kLinearStress =
    "linear elastic stress (Hooke's law of the small strain sym grad u; rotations must be small), "
    "Pa, tension positive, at each element centroid";

}  // namespace

ElementFields element_fields(const FeBody& body, const Eigen::VectorXd& displacement) {
  ElementFields fields;
  const std::optional<FiniteStrainLaw>& law = body.finite_strain_law();
  if (!law) {
    fields.stress = element_stresses(FeModel{body.mesh(), body.material(), body.thickness()}, displacement);
    fields.stress_description = kLinearStress;
    return fields;
  }
  fields.stress = cauchy_stresses({body.mesh(), law->material, body.thickness(), law->formulation}, displacement);
  for (const Eigen::Matrix3d& F : centroid_gradients(body.mesh(), displacement))
    fields.strain.push_back(green_lagrange(F));
  const bool mixed = law->formulation != FiniteStrainFormulation::standard;
  fields.stress_description = std::string("Cauchy stress sigma = P F^T / J of the ") + to_string(law->material.law) +
                              " law (" + to_string(law->formulation) + " formulation" +
                              (mixed ? ": its volumetric part from the element's pressure" : "") +
                              ") on the current configuration, Pa, tension positive, at each element centroid";
  fields.strain_description = "Green-Lagrange strain E = (F^T F - I) / 2, dimensionless, at each element centroid";
  return fields;
}

ElementFields ElementFieldsSeries::operator()(const Eigen::VectorXd& displacement) {
  if (body_.finite_strain_law()) return element_fields(body_, displacement);
  if (!linear_stresses_) linear_stresses_.emplace(body_.mesh(), body_.material());
  ElementFields fields;
  linear_stresses_->stresses(displacement, fields.stress);
  fields.stress_description = kLinearStress;
  return fields;
}

}  // namespace csim
