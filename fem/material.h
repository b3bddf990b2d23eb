// Isotropic linear elasticity (small strain) for the finite elements of fem/.
//
// Hooke's law in Lamé form, σ = λ tr(ε) I + 2μ ε, with
//   λ = E ν / ((1 + ν)(1 − 2ν)),   μ = E / (2(1 + ν))
// (Hughes, The Finite Element Method, 2000, §2.7). λ is infinite at ν = 0.5: an incompressible law
// needs a mixed (u–p) formulation, which these displacement elements are not, hence the bound
// below.
#pragma once

#include "fem/mesh.h"

#include <cmath>
#include <sstream>

namespace csim {

struct ElasticMaterial {
  double young = 0.0;    // Young's modulus E, Pa
  double poisson = 0.0;  // Poisson's ratio ν, dimensionless
  double density = 0.0;  // ρ, kg/m³
};

// Throws FemError naming the key (young, poisson, density) unless E > 0, −1 < ν < 0.5 and ρ ≥ 0,
// all finite (the bounds of a positive-definite, compressible isotropic law).
inline void check_material(const ElasticMaterial& material) {
  auto fail = [](const char* key, double value, const char* rule) {
    std::ostringstream message;
    message << "material: " << key << " = " << value << ": " << rule;
    throw FemError(message.str());
  };
  if (!(material.young > 0.0) || !std::isfinite(material.young))
    fail("young", material.young, "Young's modulus E must be finite and > 0 Pa");
  if (!std::isfinite(material.poisson) || material.poisson <= -1.0)
    fail("poisson", material.poisson, "ν must be finite and > −1");
  if (material.poisson >= 0.5)
    fail("poisson", material.poisson, "ν must be < 0.5 for a compressible law");
  if (!(material.density >= 0.0) || !std::isfinite(material.density))
    fail("density", material.density, "density ρ must be finite and ≥ 0 kg/m³");
}

// Lamé's first parameter λ and the shear modulus μ, Pa. The material must pass check_material.
inline double lame_lambda(const ElasticMaterial& material) {
  const double nu = material.poisson;
  return material.young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
}
inline double shear_modulus(const ElasticMaterial& material) {
  return material.young / (2.0 * (1.0 + material.poisson));
}

}  // namespace csim
