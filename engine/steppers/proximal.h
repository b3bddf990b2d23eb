// The proximal term of an iteration matrix that must be positive definite (a tangent stiffness, or
// M + h²θ²K_T, that a compressed body held only by contacts makes indefinite): ε I with ε from
// kFirstProximal times its largest diagonal entry, grown tenfold until the matrix is positive
// definite. Newton's residual is exact, so the term changes the iterations' path, not the converged
// state (quasi_static.h, structural_operators.h).
#pragma once

namespace csim {

inline constexpr double kFirstProximal = 1e-6;  // the first ε / max |diag|

// Calls positive_definite_with(ε) for ε = kFirstProximal·largest, ×10, … and returns true at the
// first ε that makes the matrix positive definite; false once ε has passed `largest` (a rigid-body
// mode not held, or a material instability: the caller says which).
template <class PositiveDefiniteWith>
bool grow_proximal_term(double largest, PositiveDefiniteWith&& positive_definite_with) {
  for (double epsilon = kFirstProximal * largest;; epsilon *= 10.0) {
    if (positive_definite_with(epsilon)) return true;
    if (epsilon > largest) return false;
  }
}

}  // namespace csim
