// W applied through its body-block factors (friction_contact_problem.h, BodyBlockDelassus): the scaled
// body velocities w_b = Σ_c K_cbᵀ r_c of impulses r, and from them a contact's (W r)_c = Σ_b K_cb w_b.
// A Gauss–Seidel update of contact c reads its two bodies' w (2 · D · 6 multiply-adds) and, after its
// local solve, adds K_cbᵀ Δr_c to them (as many): sparse_pgs.cpp's matrix-free sweep. Internal to contact/.
#pragma once

#include "contact/friction_contact_problem.h"

#include <Eigen/Dense>
#include <vector>

namespace csim {

template <int D>
class BodyBlockVelocities {
 public:
  static constexpr int kBody = BodyBlockDelassus::kBodySize;
  using Local = Eigen::Matrix<double, D, 1>;
  using Body = Eigen::Matrix<double, kBody, 1>;

  explicit BodyBlockVelocities(const BodyBlockDelassus& blocks)
      : blocks_(blocks), w_(static_cast<std::size_t>(kBody) * blocks.bodies, 0.0) {}

  // w ← Σ_c K_cᵀ r_c (only the bodies of these contacts are written: a solve of an island costs its
  // contacts, not the World's bodies).
  void assign(const Eigen::VectorXd& r) {
    const int contacts = static_cast<int>(blocks_.body.size());
    for (int c = 0; c < contacts; ++c)
      for (int side = 0; side < 2; ++side)
        if (const int b = blocks_.body[c][side]; b >= 0) body(b).setZero();
    for (int c = 0; c < contacts; ++c) add(c, r.template segment<D>(D * c));
  }
  // (W r)_c of the r that w holds: a dot of kBody contiguous entries for each row of K, and for an update
  // one pass over w_b (Eigen's packets, in pairs). Plain loops, which the compiler may not reorder, cost
  // more (1000 dropped spheres' pile, callgrind: about 250 instructions a contact's update through
  // Eigen's column-major D × 6 products, 290 by scalar loops, 230 so).
  Local velocity(int c) const {
    Local u;
    for (int i = 0; i < D; ++i) u(i) = 0.0;
    for (int side = 0; side < 2; ++side)
      if (const int b = blocks_.body[c][side]; b >= 0) {
        const Eigen::Map<const Body> w = body(b);
        for (int i = 0; i < D; ++i) u(i) += row(c, side, i).dot(w);
      }
    return u;
  }
  // w += K_cᵀ Δr_c: the impulse of contact c changed by dr.
  void add(int c, const Local& dr) {
    for (int side = 0; side < 2; ++side)
      if (const int b = blocks_.body[c][side]; b >= 0) {
        if constexpr (D == 3) body(b) += dr(0) * row(c, side, 0) + dr(1) * row(c, side, 1) + dr(2) * row(c, side, 2);
        else body(b) += dr(0) * row(c, side, 0) + dr(1) * row(c, side, 1);
      }
  }
  // W_cc = Σ_b K_cb K_cbᵀ.
  Eigen::Matrix<double, D, D> diagonal(int c) const {
    Eigen::Matrix<double, D, D> W_cc = Eigen::Matrix<double, D, D>::Zero();
    for (int side = 0; side < 2; ++side)
      if (blocks_.body[c][side] >= 0)
        for (int i = 0; i < D; ++i)
          for (int j = 0; j < D; ++j) W_cc(i, j) += row(c, side, i).dot(row(c, side, j));
    return W_cc;
  }

 private:
  Eigen::Map<const Body> row(int c, int side, int i) const {
    return Eigen::Map<const Body>(blocks_.scaled_rows.data() + (static_cast<std::size_t>(2 * c + side) * D + i) * kBody);
  }
  Eigen::Map<Body> body(int b) { return Eigen::Map<Body>(w_.data() + static_cast<std::size_t>(kBody) * b); }
  Eigen::Map<const Body> body(int b) const {
    return Eigen::Map<const Body>(w_.data() + static_cast<std::size_t>(kBody) * b);
  }

  const BodyBlockDelassus& blocks_;
  std::vector<double> w_;
};

}  // namespace csim
