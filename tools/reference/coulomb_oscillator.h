// Exact motion of the Coulomb-damped oscillator: the analytical reference of the Code_Aster benchmarks
// SDNV104 (rigid shoe pushed against a return spring) and SDND100 (release of a friction pad).
//
// A mass m (kg) on a spring k (N/m, at rest at x = 0) is driven by λ(t)·F (N) and resisted by Coulomb
// friction of threshold μ·λ(t)·N (N). The load factor λ(t) = min(t/τ, 1) ramps the push and the
// pressure together, as in SDNV104; τ = 0 applies both at once (λ = 1).
//   slip (velocity sign s, or about to move in direction s):  m x'' + k x = λ(t)·(F − s·μN);
//   stick: x' = 0 while |λF − k x| ≤ μλN, ending when that inequality is violated, the slip then
//   starting in the direction of λF − k x.
//
// Exactness: every phase has a closed form, x(t) = c0 + c1·u + A cos ωu + B sin ωu with u = t − t0 and
// ω = √(k/m): the particular solution c0 + c1·u follows the (linear-in-time) load, the harmonic part the
// initial state. The events are solved in closed form as well: a velocity zero c1 + ωR·sin(α − ωu) = 0 by
// an arcsine, a stick release by the root of a linear function, the ramp end is t = τ. So the solution
// is exact to rounding; no time step is involved.
#pragma once

#include <vector>

namespace csim {

struct CoulombOscillator {
  double mass = 1;          // kg, > 0
  double stiffness = 1;     // N/m, > 0
  double force = 0;         // N, driving force at full load (λ = 1), along +x when positive
  double normal_force = 0;  // N, ≥ 0, pressure at full load
  double mu = 0;            // –, ≥ 0, Coulomb coefficient
  double ramp_time = 0;     // s, ≥ 0; 0 = loads applied at once
  double x0 = 0;            // m, initial position
  double v0 = 0;            // m/s, initial velocity
};

// Built once over [0, t_end] (s), queried many times.
class CoulombOscillatorSolution {
 public:
  // Throws std::invalid_argument for a non-physical model (m or k ≤ 0, μ, N or τ < 0, non-finite values).
  CoulombOscillatorSolution(const CoulombOscillator& model, double t_end);

  // t in [0, t_end] (s); throws std::out_of_range otherwise.
  double position(double t) const;  // m
  double velocity(double t) const;  // m/s

  // Extrema of x(t) in [0, t_end]: the instants where the velocity changes sign or the mass comes to a
  // stop, including the final stop (the start at t = 0 is not one). Indices start at 1; an index outside
  // [1, extremum_count()] throws std::out_of_range.
  int extremum_count() const;
  double extremum_time(int index) const;   // s
  double extremum_value(int index) const;  // m

  // Whether the mass stops for good at some t ≤ t_end (true also when it never moves). rest_time() and
  // rest_position() throw std::logic_error when it does not.
  bool comes_to_rest() const;
  double rest_time() const;      // s, the instant of the final stop (0 when it never moves)
  double rest_position() const;  // m

  double natural_frequency() const { return omega_; }  // ω = √(k/m), rad/s
  double t_end() const { return t_end_; }               // s

 private:
  // One phase: slip in one direction, or stick (then c1 = A = B = 0 and c0 is the position).
  struct Piece {
    double t0 = 0;  // s, start
    double c0 = 0;  // m, particular solution at t0
    double c1 = 0;  // m/s, its rate (non-zero only while the load ramps)
    double a = 0;   // m, cosine amplitude
    double b = 0;   // m, sine amplitude
  };
  struct Extremum {
    double time;   // s
    double value;  // m
  };
  void build(const CoulombOscillator& model);
  const Piece& piece_at(double t, const char* what) const;
  const Extremum& extremum(int index) const;

  double omega_ = 1;
  double t_end_ = 0;
  std::vector<Piece> pieces_;  // contiguous in time, sorted by t0; the last one covers t_end
  std::vector<Extremum> extrema_;
  bool at_rest_ = false;
  double rest_time_ = 0;
  double rest_position_ = 0;
};

}  // namespace csim
