// The laws of hyperelastic.h. Each tangent is assembled from a few fourth-order building blocks
// (below) obtained by differentiating P term by term with
//   ∂J/∂F = J H,  ∂H_iJ/∂F_kL = −H_iL H_kJ,  H = F⁻ᵀ,
//   ∂I1/∂F = 2F,  ∂I2/∂F = 2(I1 F − bF),  I2 = ½(I1² − tr C²)
// (Holzapfel 2000, ch. 2 and 6; Bonet & Wood 2008, ch. 6).
//
// One code for both dimensions, on Dim × Dim matrices. Plane strain (Dim = 2) holds
// F = [[F2, 0], [0, 1]], so F, C, b, H and every product of them are block diagonal with 1 in the
// out-of-plane slot: their in-plane blocks are the 2×2 products of the in-plane blocks (H2 = F2⁻ᵀ,
// C2 = F2ᵀF2, (bF)2 = b2 F2, det F = det F2), and each term of A on in-plane indices involves
// in-plane entries only. The out-of-plane 1 shows only in traces and norms (I1 = tr C2 + 1,
// tr C² = ‖C2‖² + 1, ‖F‖² = ‖F2‖² + 1): whole_trace and whole_squared_norm add it. Two 2×2
// identities make plane strain cheaper still: X_iL X_kJ = X_iJ X_kL − det X ε_ik ε_JL for any 2×2 X
// (add_cross), and Cayley–Hamilton, which collapses Mooney–Rivlin's bF and I2 to F, H and J: its
// plane variant, mooney_rivlin_plane_part, stands beside the general mooney_rivlin_part. The 3D code
// (Dim = 3) is the general one; tests/fem/hyperelastic_test.cpp checks the plane one against it.
#include "fem/hyperelastic.h"

#include "fem/material.h"

#include <cmath>
#include <sstream>

namespace csim {
namespace {

template <int Dim>
using Square = Eigen::Matrix<double, Dim, Dim>;

// tr X and X:X of the 3×3 tensor whose in-plane block is X (Dim = 2: with 1 out of the plane, as
// C and b have in plane strain).
template <int Dim>
double whole_trace(const Square<Dim>& X) {
  if constexpr (Dim == 2) return X.trace() + 1.0;
  else return X.trace();
}
template <int Dim>
double whole_squared_norm(const Square<Dim>& X) {
  if constexpr (Dim == 2) return X.squaredNorm() + 1.0;
  else return X.squaredNorm();
}

// The building blocks write A_iJkL for i, J, k, L < Dim, flattened with stride Dim: Dim = 3 is the
// whole tangent, Dim = 2 its in-plane block (plane strain): 16 entries where the whole has 81.
template <int Dim>
using Flat = Eigen::Matrix<double, Dim * Dim, 1>;

// X flattened row by row, the order of A's rows and columns.
template <int Dim>
Flat<Dim> flatten(const Square<Dim>& X) {
  Flat<Dim> v;
  for (int i = 0; i < Dim; ++i)
    for (int J = 0; J < Dim; ++J) v(Dim * i + J) = X(i, J);
  return v;
}

// A_iJkL += c (X_iJ Y_kL + Y_iJ X_kL): the symmetric dyad.
template <int Dim>
void add_symmetric_dyad(MaterialTangentOf<Dim>& A, double c, const Square<Dim>& X,
                        const Square<Dim>& Y) {
  const Flat<Dim> x = flatten<Dim>(X), y = flatten<Dim>(Y);
  A.noalias() += c * (x * y.transpose() + y * x.transpose());
}

// A_iJkL += c X_iJ X_kL.
template <int Dim>
void add_dyad(MaterialTangentOf<Dim>& A, double c, const Square<Dim>& X) {
  const Flat<Dim> x = flatten<Dim>(X);
  A.noalias() += c * (x * x.transpose());
}

// A_iJkL += c X_iL X_kJ (from the derivative of an inverse or of a product FᵀF). A 2×2 X has
// X_iL X_kJ = X_iJ X_kL − det X ε_ik ε_JL (ε the 2D permutation symbol; both sides vanish unless
// i ≠ k and J ≠ L), so in plane strain it is a dyad and ∓c det X on the (F11, F22) and (F12, F21)
// pairs, a third of the loop's cost.
template <int Dim>
void add_cross(MaterialTangentOf<Dim>& A, double c, const Square<Dim>& X) {
  if constexpr (Dim == 2) {
    add_dyad<2>(A, c, X);
    const double d = c * X.determinant();
    A(0, 3) -= d, A(3, 0) -= d;
    A(1, 2) += d, A(2, 1) += d;
  } else {
    for (int i = 0; i < Dim; ++i)
      for (int J = 0; J < Dim; ++J)
        for (int k = 0; k < Dim; ++k)
          for (int L = 0; L < Dim; ++L) A(Dim * i + J, Dim * k + L) += c * X(i, L) * X(k, J);
  }
}

// A_iJkL += c (δik S_JL + T_ik δJL), S and T symmetric; S = T = I gives 2c δik δJL.
template <int Dim>
void add_kronecker(MaterialTangentOf<Dim>& A, double c, const Square<Dim>& S,
                   const Square<Dim>& T) {
  for (int i = 0; i < Dim; ++i)
    for (int J = 0; J < Dim; ++J)
      for (int L = 0; L < Dim; ++L) {
        A(Dim * i + J, Dim * i + L) += c * S(J, L);
        A(Dim * J + i, Dim * L + i) += c * T(J, L);
      }
}

[[noreturn]] void throw_inverted(double J) {
  std::ostringstream message;
  message << "hyperelastic material: det F = " << J << " ≤ 0 or not finite (inverted)";
  throw FemError(message.str());
}

// The message is built out of line, so that this check inlines into every evaluation.
template <int Dim>
double checked_determinant(const Square<Dim>& F) {
  const double J = F.determinant();
  if (!(J > 0.0) || !std::isfinite(J)) throw_inverted(J);
  return J;
}

// J^(−1/3), J > 0. Near J = 1, where nearly incompressible materials stay, by Newton's method on
// r⁻³ = J from r = 1, r ← r (4 − J r³)/3: the relative error e becomes −2e² + O(e³), so four steps
// take |e| < 0.035 (|J − 1| < 0.1) below round-off, at a sixth of std::cbrt's cost (glibc's goes
// through frexp and ldexp); elsewhere std::cbrt.
double inverse_cube_root(double J) {
  if (!(std::abs(J - 1.0) < 0.1)) return 1.0 / std::cbrt(J);
  double r = 1.0;
  for (int step = 0; step < 4; ++step) r *= (4.0 - J * (r * r * r)) / 3.0;
  return r;
}

// S = λ tr E I + 2μ E, P = FS; A = δik S_JL + λ F_iJ F_kL + μ (F_iL F_kJ + b_ik δJL). Plane
// strain: E33 = 0, so tr E and E:E are the in-plane block's.
template <int Dim>
void saint_venant_kirchhoff_part(const HyperelasticMaterial& m, const Square<Dim>& F,
                                 bool with_tangent, HyperelasticResponseOf<Dim>& r) {
  const Square<Dim> I = Square<Dim>::Identity();
  const Square<Dim> E = 0.5 * (F.transpose() * F - I);
  const double trace = E.trace();
  const Square<Dim> S = m.lambda * trace * I + 2.0 * m.mu * E;
  r.energy = 0.5 * m.lambda * trace * trace + m.mu * E.squaredNorm();
  r.stress = F * S;
  if (!with_tangent) return;
  add_kronecker<Dim>(r.tangent, 1.0, S, m.mu * F * F.transpose());
  add_dyad<Dim>(r.tangent, m.lambda, F);
  add_cross<Dim>(r.tangent, m.mu, F);
}

// W_iso = μ/2 (I1 − 3) − μ ln J: P = μ(F − H), A = μ δik δJL + μ H_iL H_kJ.
template <int Dim>
void neo_hookean_part(const HyperelasticMaterial& m, const Square<Dim>& F, double J,
                      bool with_tangent, HyperelasticResponseOf<Dim>& r) {
  const Square<Dim> H = F.inverse().transpose();
  r.energy = 0.5 * m.mu * (whole_squared_norm<Dim>(F) - 3.0) - m.mu * std::log(J);
  r.stress = m.mu * (F - H);
  if (!with_tangent) return;
  const Square<Dim> I = Square<Dim>::Identity();
  add_kronecker<Dim>(r.tangent, 0.5 * m.mu, I, I);
  add_cross<Dim>(r.tangent, m.mu, H);
}

// W_iso = C10 (a I1 − 3) + C01 (c I2 − 3), a = J^(−2/3), c = J^(−4/3). With ∂a = −⅔ a H and
// ∂c = −(4/3) c H:
//   ∂(a I1)  = a (2F − ⅔ I1 H)
//   ∂²(a I1) = a [ (4/9) I1 H⊗H + ⅔ I1 H_iL H_kJ − (4/3)(H⊗F + F⊗H) + 2 δik δJL ]
//   ∂(c I2)  = c (D − (4/3) I2 H),  D = ∂I2/∂F = 2(I1 F − bF)
//   ∂²(c I2) = c [ (16/9) I2 H⊗H + (4/3) I2 H_iL H_kJ − (4/3)(H⊗D + D⊗H)
//                  + 4 F⊗F + 2 I1 δik δJL − 2 δik C_JL − 2 F_iL F_kJ − 2 b_ik δJL ]
template <int Dim>
void mooney_rivlin_part(const HyperelasticMaterial& m, const Square<Dim>& F, double J,
                        bool with_tangent, HyperelasticResponseOf<Dim>& r) {
  const Square<Dim> H = F.inverse().transpose();
  const Square<Dim> C = F.transpose() * F, b = F * F.transpose();
  const double I1 = whole_trace<Dim>(C);
  const double I2 = 0.5 * (I1 * I1 - whole_squared_norm<Dim>(C));
  const double root = inverse_cube_root(J);
  const double a = root * root, c = a * a;
  const Square<Dim> D = 2.0 * (I1 * F - b * F);
  r.energy = m.c10 * (a * I1 - 3.0) + m.c01 * (c * I2 - 3.0);
  r.stress = m.c10 * a * (2.0 * F - (2.0 / 3.0) * I1 * H) + m.c01 * c * (D - (4.0 / 3.0) * I2 * H);
  if (!with_tangent) return;
  // C10 ∂²(a I1) + C01 ∂²(c I2), the terms of each kind summed before they are spread over A's
  // entries: the H⊗F and H⊗D dyads make one, the δik δJL, δik C_JL and b_ik δJL terms another.
  const double first = m.c10 * a, second = m.c01 * c;
  const Square<Dim> I = Square<Dim>::Identity();
  const Square<Dim> shear = first * F + second * D;
  const double kronecker = first + second * I1;
  add_dyad<Dim>(r.tangent, first * (4.0 / 9.0) * I1 + second * (16.0 / 9.0) * I2, H);
  add_cross<Dim>(r.tangent, first * (2.0 / 3.0) * I1 + second * (4.0 / 3.0) * I2, H);
  add_symmetric_dyad<Dim>(r.tangent, -4.0 / 3.0, H, shear);
  add_dyad<Dim>(r.tangent, 4.0 * second, F);
  add_kronecker<Dim>(r.tangent, 1.0, kronecker * I - 2.0 * second * C, kronecker * I - 2.0 * second * b);
  add_cross<Dim>(r.tangent, -2.0 * second, F);
}

// The same in plane strain, where the 2×2 identities collapse the law. Cayley–Hamilton for b2,
// b2² = tr b2 b2 − J² I, gives bF = (I1 − 1) F − J² H, hence D = 2(F + J² H) and
// I2 = I1 − 1 + J²; and X_iL X_kJ = X_iJ X_kL − det X ε_ik ε_JL (add_cross) turns both cross terms
// into dyads. A is then a quadratic form in H and F, the Kronecker terms and a multiple of
// ε_ik ε_JL (det H = 1/J, det F = J):
//   A = a_HH H⊗H + a_FF F⊗F + a_HF (H⊗F + F⊗H) + δik S_JL + T_ik δJL + e ε_ik ε_JL,
//   a_HH = α + β − (16/3) C01 c J², a_FF = 2 C01 c, a_HF = −(4/3)(C10 a + 2 C01 c),
//   e = 2 C01 c J − β/J, with α, β the coefficients of H⊗H and H_iL H_kJ above.
void mooney_rivlin_plane_part(const HyperelasticMaterial& m, const Square<2>& F, double J,
                              bool with_tangent, HyperelasticResponseOf<2>& r) {
  const Square<2> H = F.inverse().transpose();
  const Square<2> C = F.transpose() * F;
  const double I1 = whole_trace<2>(C);
  const double I2 = I1 - 1.0 + J * J;
  const double root = inverse_cube_root(J);
  const double a = root * root, c = a * a;
  const double first = m.c10 * a, second = m.c01 * c;
  r.energy = m.c10 * (a * I1 - 3.0) + m.c01 * (c * I2 - 3.0);
  // C10 a (2F − ⅔ I1 H) + C01 c (D − (4/3) I2 H), D = 2(F + J² H)
  r.stress = 2.0 * (first + second) * F +
             (second * (2.0 * J * J - (4.0 / 3.0) * I2) - first * (2.0 / 3.0) * I1) * H;
  if (!with_tangent) return;
  const double alpha = first * (4.0 / 9.0) * I1 + second * (16.0 / 9.0) * I2;
  const double beta = first * (2.0 / 3.0) * I1 + second * (4.0 / 3.0) * I2;
  const double a_HH = alpha + beta - (16.0 / 3.0) * second * J * J;
  const double a_HF = -(4.0 / 3.0) * (first + 2.0 * second), a_FF = 2.0 * second;
  Eigen::Matrix<double, 4, 2> basis;  // H and F flattened
  basis.col(0) = flatten<2>(H);
  basis.col(1) = flatten<2>(F);
  Eigen::Matrix2d form;
  form << a_HH, a_HF, a_HF, a_FF;
  r.tangent.noalias() += basis * form * basis.transpose();
  const double kronecker = first + second * I1;
  const Square<2> I = Square<2>::Identity();
  add_kronecker<2>(r.tangent, 1.0, kronecker * I - 2.0 * second * C,
                   kronecker * I - 2.0 * second * F * F.transpose());
  const double e = 2.0 * second * J - beta / J;
  r.tangent(0, 3) += e, r.tangent(3, 0) += e;
  r.tangent(1, 2) -= e, r.tangent(2, 1) -= e;
}

}  // namespace

const char* to_string(HyperelasticLaw law) {
  switch (law) {
    case HyperelasticLaw::saint_venant_kirchhoff: return "saint_venant_kirchhoff";
    case HyperelasticLaw::neo_hookean: return "neo_hookean";
    case HyperelasticLaw::mooney_rivlin: return "mooney_rivlin";
  }
  return "unknown";
}

namespace {

HyperelasticMaterial from_young_poisson(HyperelasticLaw law, double young, double poisson,
                                        double density) {
  const ElasticMaterial elastic{young, poisson, density};
  check_material(elastic);
  HyperelasticMaterial material;
  material.law = law;
  material.lambda = lame_lambda(elastic);
  material.mu = shear_modulus(elastic);
  material.density = density;
  return material;
}

}  // namespace

HyperelasticMaterial saint_venant_kirchhoff(double young, double poisson, double density) {
  return from_young_poisson(HyperelasticLaw::saint_venant_kirchhoff, young, poisson, density);
}

HyperelasticMaterial neo_hookean(double young, double poisson, double density) {
  return from_young_poisson(HyperelasticLaw::neo_hookean, young, poisson, density);
}

HyperelasticMaterial mooney_rivlin(double c10, double c01, double bulk, double density) {
  HyperelasticMaterial material;
  material.law = HyperelasticLaw::mooney_rivlin;
  material.c10 = c10;
  material.c01 = c01;
  material.bulk = bulk;
  material.density = density;
  check_hyperelastic(material);
  return material;
}

void check_hyperelastic(const HyperelasticMaterial& material) {
  auto fail = [](const char* key, double value, const char* rule) {
    std::ostringstream message;
    message << "hyperelastic material: " << key << " = " << value << ": " << rule;
    throw FemError(message.str());
  };
  auto finite = [&](const char* key, double value) {
    if (!std::isfinite(value)) fail(key, value, "must be finite");
  };
  switch (material.law) {
    case HyperelasticLaw::saint_venant_kirchhoff:
    case HyperelasticLaw::neo_hookean:
      finite("mu", material.mu);
      finite("lambda", material.lambda);
      if (!(material.mu > 0.0)) fail("mu", material.mu, "shear modulus μ must be > 0 Pa (E > 0)");
      if (!(material.lambda > -2.0 / 3.0 * material.mu))
        fail("lambda", material.lambda,
             "λ must be > −2μ/3, a positive bulk modulus (−1 < ν < 0.5)");
      break;
    case HyperelasticLaw::mooney_rivlin:
      finite("c10", material.c10);
      finite("c01", material.c01);
      finite("bulk", material.bulk);
      if (!(material.c10 + material.c01 > 0.0))
        fail("c10", material.c10, "C10 + C01 must be > 0 Pa (positive initial shear modulus)");
      if (!(material.bulk > 0.0)) fail("bulk", material.bulk, "bulk modulus K must be > 0 Pa");
      break;
    default: throw FemError("hyperelastic material: unknown law");
  }
  finite("density", material.density);
  if (!(material.density >= 0.0)) fail("density", material.density, "density ρ must be ≥ 0 kg/m³");
}

InitialModuli initial_moduli(const HyperelasticMaterial& material) {
  if (material.law == HyperelasticLaw::mooney_rivlin) {
    const double mu = 2.0 * (material.c10 + material.c01);
    return {material.bulk - 2.0 / 3.0 * mu, mu};
  }
  return {material.lambda, material.mu};
}

template <int Dim>
HyperelasticResponseOf<Dim> isochoric_response(const HyperelasticMaterial& material,
                                             const GradientOf<Dim>& F, bool with_tangent) {
  const double J = checked_determinant<Dim>(F);
  HyperelasticResponseOf<Dim> response;
  switch (material.law) {
    case HyperelasticLaw::saint_venant_kirchhoff:
      saint_venant_kirchhoff_part(material, F, with_tangent, response);
      break;
    case HyperelasticLaw::neo_hookean:
      neo_hookean_part(material, F, J, with_tangent, response);
      break;
    case HyperelasticLaw::mooney_rivlin:
      if constexpr (Dim == 2) mooney_rivlin_plane_part(material, F, J, with_tangent, response);
      else mooney_rivlin_part(material, F, J, with_tangent, response);
      break;
  }
  return response;
}

VolumetricResponse volumetric_response(const HyperelasticMaterial& material, double J) {
  if (!(J > 0.0) || !std::isfinite(J)) {
    std::ostringstream message;
    message << "hyperelastic material: J = " << J << " ≤ 0 or not finite (inverted)";
    throw FemError(message.str());
  }
  switch (material.law) {
    case HyperelasticLaw::saint_venant_kirchhoff: return {};
    case HyperelasticLaw::neo_hookean: {
      const double log_J = std::log(J);
      return {0.5 * material.lambda * log_J * log_J, material.lambda * log_J / J,
              material.lambda * (1.0 - log_J) / (J * J)};
    }
    case HyperelasticLaw::mooney_rivlin:
      return {0.5 * material.bulk * (J - 1.0) * (J - 1.0), material.bulk * (J - 1.0),
              material.bulk};
  }
  return {};
}

// W = W_iso + U(J): P_vol = U' J H, A_vol = (U'' J² + U' J) H⊗H − U' J H_iL H_kJ.
template <int Dim>
HyperelasticResponseOf<Dim> hyperelastic_response(const HyperelasticMaterial& material,
                                                const GradientOf<Dim>& F, bool with_tangent) {
  HyperelasticResponseOf<Dim> response = isochoric_response<Dim>(material, F, with_tangent);
  if (material.law == HyperelasticLaw::saint_venant_kirchhoff) return response;
  const double J = F.determinant();
  const VolumetricResponse volumetric = volumetric_response(material, J);
  const Square<Dim> H = F.inverse().transpose();
  response.energy += volumetric.energy;
  response.stress += volumetric.mean_stress * J * H;
  if (with_tangent) {
    add_dyad<Dim>(response.tangent, volumetric.stiffness * J * J + volumetric.mean_stress * J, H);
    add_cross<Dim>(response.tangent, -volumetric.mean_stress * J, H);
  }
  return response;
}

template HyperelasticResponseOf<2> isochoric_response<2>(const HyperelasticMaterial&,
                                                         const GradientOf<2>&, bool);
template HyperelasticResponseOf<3> isochoric_response<3>(const HyperelasticMaterial&,
                                                         const GradientOf<3>&, bool);
template HyperelasticResponseOf<2> hyperelastic_response<2>(const HyperelasticMaterial&,
                                                            const GradientOf<2>&, bool);
template HyperelasticResponseOf<3> hyperelastic_response<3>(const HyperelasticMaterial&,
                                                            const GradientOf<3>&, bool);

}  // namespace csim
