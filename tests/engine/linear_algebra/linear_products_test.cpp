// K and M applied to several vectors in one pass (linear_products.h), and a linear World's step-end
// products through Dynamics::linear_products.
#include "engine/linear_algebra/linear_products.h"

#include "engine/dynamics.h"
#include "tools/run/run.h"
#include "tools/scene/scene.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

namespace csim {
namespace {

// A symmetric n × n matrix with about `density` of its entries set; with zero_diagonal, its diagonal is
// left out.
SparseMatrix random_symmetric(int n, double density, bool zero_diagonal, std::mt19937& random) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0), draw(0.0, 1.0);
  Triplets entries;
  for (int j = 0; j < n; ++j) {
    if (!zero_diagonal) entries.emplace_back(j, j, 4.0 + uniform(random));
    for (int i = j + 1; i < n; ++i)
      if (draw(random) < density) {
        const double value = uniform(random);
        entries.emplace_back(i, j, value);
        entries.emplace_back(j, i, value);
      }
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  return A;
}

bool same_bits(const Vector& a, const Vector& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

double relative_gap(const Vector& got, const Vector& expected) {
  return (got - expected).norm() / std::max(expected.norm(), 1e-300);
}

// Each product is Eigen's separate sparse product to the bit: K as blocks at their offsets (rows and
// columns outside every block are K's zeros; q read at the blocks' position offsets), M with entries
// where K has none and the reverse, with and without M dv; a misplaced block is refused.
TEST(LinearProducts, AreEigensSeparateProductsToTheBit) {
  std::mt19937 random(11);
  std::normal_distribution<double> normal;
  const int n = 37;
  const SparseMatrix K_1 = random_symmetric(6, 0.5, false, random), K_2 = random_symmetric(19, 0.3, true, random);
  const SparseMatrix M = random_symmetric(n, 0.1, false, random);
  // Position offsets past the velocity ones, as after a body with a quaternion (7 positions, 6 velocities).
  const LinearProducts products({{2, 3, &K_1}, {12, 15, &K_2}}, M);
  EXPECT_EQ(products.size(), n);
  SparseMatrix K(n, n);
  {
    Triplets entries;
    for (const auto& [offset, A] : {std::pair{2, &K_1}, std::pair{12, &K_2}})
      for (int j = 0; j < A->outerSize(); ++j)
        for (SparseMatrix::InnerIterator it(*A, j); it; ++it) entries.emplace_back(offset + it.row(), offset + it.col(), it.value());
    K.setFromTriplets(entries.begin(), entries.end());
  }
  Vector q(n + 4), v(n), dv(n);
  for (int i = 0; i < n + 4; ++i) q(i) = normal(random);
  for (int i = 0; i < n; ++i) v(i) = normal(random), dv(i) = normal(random);
  Vector q_in_v = Vector::Zero(n);  // the blocks' positions where their velocities are
  q_in_v.segment(2, 6) = q.segment(3, 6);
  q_in_v.segment(12, 19) = q.segment(15, 19);
  Vector Kq, Kv, Mv, Mdv;
  products.multiply(q, v, &dv, Kq, Kv, Mv, &Mdv);
  const Vector Kq_eigen = K * q_in_v, Kv_eigen = K * v, Mv_eigen = M * v, Mdv_eigen = M * dv;
  EXPECT_TRUE(same_bits(Kq, Kq_eigen));
  EXPECT_TRUE(same_bits(Kv, Kv_eigen));
  EXPECT_TRUE(same_bits(Mv, Mv_eigen));
  EXPECT_TRUE(same_bits(Mdv, Mdv_eigen));
  EXPECT_EQ(Kq.head(2), Vector::Zero(2));
  EXPECT_EQ(Kq.segment(8, 4), Vector::Zero(4));
  EXPECT_GT(Kq.segment(12, 19).norm(), 0.0);

  Vector Kq_alone, Kv_alone, Mv_alone, untouched = Vector::Constant(3, 2.5), Kx;
  products.multiply(q, v, nullptr, Kq_alone, Kv_alone, Mv_alone, &untouched);
  EXPECT_TRUE(same_bits(Kq_alone, Kq_eigen));
  EXPECT_TRUE(same_bits(Mv_alone, Mv_eigen));
  EXPECT_EQ(untouched, Vector::Constant(3, 2.5));
  products.multiply_stiffness(v, Kx);
  EXPECT_TRUE(same_bits(Kx, Kv_eigen));

  EXPECT_THROW(LinearProducts({{12, 12, &K_2}, {2, 2, &K_1}}, M), std::invalid_argument);
  EXPECT_THROW(LinearProducts({{20, 20, &K_2}}, M), std::invalid_argument);
}

// A linear World's step-end products, on the elastic QUAD4 shoe of SDNV104 on two springs and on a rigid
// box with a quaternion before an elastic block (q's offsets past v's): K v with the springs' part
// against the assembled K (to round-off: the springs' part is added apart), M v and M dv to the bit,
// apply_linear_stiffness's K v to the bit, and the K q kept: the elastic energy and the internal forces
// at q read afterwards are a fresh Dynamics' to the bit.
TEST(LinearProducts, LinearWorldStepEndProductsAreTheAssembledOnes) {
  int worlds = 0;
  for (const auto& [scene_file, overrides] :
       {std::pair{std::string(CSIM_SOURCE_DIR "/scenes/sdnv104-quad4/scene.yaml"),
                  std::vector<std::string>{"parameters.divisions=4"}},
        std::pair{std::string(CSIM_SOURCE_DIR "/tests/engine/data/box_before_block_3d.yaml"), std::vector<std::string>{}}}) {
    const auto scene = load_scene(scene_file, overrides);
    const Dynamics dynamics(scene->world), fresh(scene->world);
    const int n = dynamics.size();
    Vector q = initial_state(scene->world).q, v(n), dv(n);
    for (int i = 0; i < q.size(); ++i) q(i) += 1e-3 * std::sin(0.7 * i);
    for (int i = 0; i < n; ++i) {
      v(i) = std::cos(1.3 * i);
      dv(i) = std::sin(2.1 * i + 0.4);
    }
    Vector Kv, Mv, Mdv, Kv_alone;
    dynamics.linear_products(q, v, &dv, Kv, Mv, &Mdv);
    dynamics.apply_linear_stiffness(q, v, Kv_alone);
    EXPECT_TRUE(same_bits(Kv, Kv_alone)) << scene_file;
    Triplets entries;
    dynamics.add_stiffness(q, entries);  // the bodies' and the springs'
    SparseMatrix K(n, n);
    K.setFromTriplets(entries.begin(), entries.end());
    // The springs' part is far above the tolerance: without it the check below would fail.
    if (dynamics.has_springs()) {
      EXPECT_GT(relative_gap(dynamics.body_stiffness() * v, K * v), 1e-10) << scene_file;
    }
    EXPECT_LT(relative_gap(Kv, K * v), 1e-13) << scene_file;
    const Vector Mv_eigen = dynamics.mass() * v, Mdv_eigen = dynamics.mass() * dv;
    EXPECT_TRUE(same_bits(Mv, Mv_eigen)) << scene_file;
    EXPECT_TRUE(same_bits(Mdv, Mdv_eigen)) << scene_file;

    const double energy = dynamics.elastic_energy(q), fresh_energy = fresh.elastic_energy(q);
    EXPECT_GT(energy, 0.0) << scene_file;
    EXPECT_EQ(std::memcmp(&energy, &fresh_energy, sizeof(double)), 0) << scene_file;
    Vector f = Vector::Zero(n), fresh_f = Vector::Zero(n);
    dynamics.add_internal_forces(q, f);
    fresh.add_internal_forces(q, fresh_f);
    EXPECT_GT(fresh_f.norm(), 0.0) << scene_file;
    EXPECT_TRUE(same_bits(f, fresh_f)) << scene_file;
    ++worlds;
  }
  EXPECT_EQ(worlds, 2);
}

}  // namespace
}  // namespace csim
