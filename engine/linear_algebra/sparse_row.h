// One row of the contact Jacobian H: u_row = Σ_k value[k] · v[index[k]], over at most fifteen velocity
// components (a contact joins two bodies: a rigid body moves its point through at most six, an
// elastic body's face point through the nine of a boundary triangle's nodes). Stored this way
// a contact costs a handful of numbers whatever the size of the bodies, which keeps a step linear in
// the number of unknowns for finite-element bodies.
#pragma once

#include "engine/bodies/body.h"

#include <array>

namespace csim {

struct SparseRow {
  // User-provided, so that a vector of rows resized in every step is not zero-filled: only the first
  // `count` entries are ever read.
  SparseRow() {}
  int count = 0;
  std::array<int, 15> index;
  std::array<double, 15> value;

  void clear() { count = 0; }
  void add(int i, double x) {
    for (int k = 0; k < count; ++k)
      if (index[k] == i) {
        value[k] += x;
        return;
      }
    index[count] = i;
    value[count++] = x;
  }
  double dot(const Vector& v) const {
    double sum = 0.0;
    for (int k = 0; k < count; ++k) sum += value[k] * v(index[k]);
    return sum;
  }
  template <class Dense>  // a Vector, or a row of a dense matrix
  void scatter(double scale, Dense&& f) const {  // f += scale · rowᵀ
    for (int k = 0; k < count; ++k) f(index[k]) += scale * value[k];
  }
  bool operator==(const SparseRow& other) const {
    if (count != other.count) return false;
    for (int k = 0; k < count; ++k)
      if (index[k] != other.index[k] || value[k] != other.value[k]) return false;
    return true;
  }
};

}  // namespace csim
