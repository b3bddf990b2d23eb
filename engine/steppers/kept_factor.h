// Modified Newton's bookkeeping for the quasi-static stepper (quasi_static.h): what the factor of a load
// step's last factored iterate was made with, and whether a later iterate of the same step may solve
// with it instead of factoring its own tangent.
//
// The kept matrix A is one of K_z (positive definite on its own), K_z + G + ρ H_Aᵀ H_A (the held rows)
// or K_z + proximal terms. An iterate solves with it, its own residual, rows and Delassus operator
// H A⁻¹ Hᵀ taken with the kept A, so that a fixed point is the equilibrium whatever A is (quasi_static.h);
// what A must share with the iterate is what makes it a good model there:
//   held rows: the same contacts held the same way (a row held in A that the iterate lets go would be
//   stiffened by ρ where it is free), with the same least weight held_weight;
//   proximal terms: the same hub weight, and rows that would not hold K_z either (no held row, or a hub
//   without a sticking one), since the iterate's own factor would then be held;
//   and, after an iterate that kept it, a contraction |Δz_j|∞ ≤ kContraction |Δz_{j−1}|∞: past that, a
//   factor of the iterate's own tangent converges faster than the kept one.
// Iterates that keep one A are a fixed-point iteration z ← z + Δz(z), whose observed contraction
// θ = |Δz_j|∞ / |Δz_{j−1}|∞ bounds the distance of z_{j+1} = z_j + Δz_j to its fixed point (the
// equilibrium) by θ/(1−θ) |Δz_j|∞ (the a-posteriori bound of a contraction): distance_bound, which the
// stepper's convergence test reads beside |Δz_j|∞ itself. θ is taken between two iterates that both
// kept A: the ratio to the iterate that factored A is a Newton step's, far below the kept iteration's
// contraction once Newton converges quadratically (0.007 against 0.05 on a rolling ring).
#pragma once

#include "contact/contact_point.h"

#include <utility>
#include <vector>

namespace csim {

// The rows of a contact that a Newton iterate holds (quasi_static.h): none, the normal, or all (sticking).
enum class Hold { none = 0, normal = 1, stick = 2 };
// The contacts an iterate holds, and how, in its contacts' order (sorted by key).
using HeldRows = std::vector<std::pair<ContactKey, Hold>>;
// How many of a contact's rows (of dimension d) are held: none, the normal, or all of them.
inline int held_row_count(Hold hold, int dimension) {
  return hold == Hold::stick ? dimension : hold == Hold::normal ? 1 : 0;
}
// Whether held rows make the factored matrix K_z + G + ρ H_Aᵀ H_A (quasi_static.h) rather than the
// proximal terms: some row held, and with a hub a sticking contact to hold its spin.
bool rows_hold(const HeldRows& rows, bool hub);

class KeptFactor {
 public:
  static constexpr double kContraction = 0.5;

  enum class Kind { stiffness, held, proximal };  // K_z itself; K_z + G + ρ H_Aᵀ H_A; K_z + proximal terms
  struct Made {
    Kind kind = Kind::stiffness;
    HeldRows rows;              // the iterate's held rows (those of A when kind is held)
    double held_weight = 0.0;   // the held rows' least ρ / max diag(K_z) the iterate started from
    double hub_proximal = 0.0;  // the hub's proximal weight / max diag(K_z) then
    double rho = 0.0;           // held: the ρ in A (N/m)
    bool regularized = false;   // proximal: grown on every unknown
  };

  void drop() { valid_ = false; }  // at a step's start: a factor of another step's matrix is not kept
  void record(Made made);          // a factor was just made (the iterate's |Δz| follows by observe)
  // After each iterate: its |Δz|∞ (m, rad), whether it kept the factor, and whether it took its whole
  // step (no relaxation, secant_relaxation.h: z_{j+1} = z_j + Δz_j).
  void observe(double increment, bool kept, bool whole_step);
  // θ/(1−θ) |Δz_j|∞ (m, rad) after two iterates that kept the factor and took their whole steps, the
  // second contracting by θ ≤ kContraction; +∞ otherwise.
  double distance_bound() const;
  // Whether the next iterate, whose warm start holds rows with these weights, may solve with the factor;
  // hub: whether the unknowns have a hub (whose held rows need a sticking contact).
  bool fits(const HeldRows& rows, double held_weight, double hub_proximal, bool hub) const;
  const Made& made() const { return made_; }

 private:
  bool valid_ = false;
  Made made_;
  bool last_kept_ = false, kept_before_ = false;
  bool whole_ = false, whole_before_ = false;
  double increment_ = 0.0, increment_before_ = 0.0;
};

}  // namespace csim
