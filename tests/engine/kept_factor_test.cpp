// Modified Newton's bookkeeping (engine/steppers/kept_factor.h): a later iterate keeps a step's factor only
// while the factor is a good model there (the same held rows and weights) and while it contracts.
#include "engine/steppers/kept_factor.h"

#include <gtest/gtest.h>

#include <limits>

namespace csim {
namespace {

ContactKey key(int feature) { return {0, 1, feature}; }

KeptFactor::Made held_factor() {
  KeptFactor::Made made;
  made.kind = KeptFactor::Kind::held;
  made.rows = {{key(3), Hold::stick}, {key(4), Hold::normal}};
  made.held_weight = 1e-4;
  made.hub_proximal = 1e-4;
  made.rho = 2.5;
  return made;
}

TEST(KeptFactor, NothingIsKeptBeforeAFactorOrAfterTheStepStart) {
  KeptFactor kept;
  EXPECT_FALSE(kept.fits({}, 1e-4, 1e-4, true));
  kept.record(held_factor());
  kept.observe(1e-3, false, true);
  EXPECT_TRUE(kept.fits(held_factor().rows, 1e-4, 1e-4, true));
  kept.drop();
  EXPECT_FALSE(kept.fits(held_factor().rows, 1e-4, 1e-4, true));
}

TEST(KeptFactor, AHeldFactorIsDroppedWhenTheHeldRowsOrTheirWeightChange) {
  KeptFactor kept;
  kept.record(held_factor());
  kept.observe(1e-3, false, true);
  const HeldRows same = held_factor().rows;
  EXPECT_TRUE(kept.fits(same, 1e-4, 1e-4, true));
  EXPECT_TRUE(kept.fits(same, 1e-4, 1e-2, true));  // the hub's weight is not in a held factor
  HeldRows slips = same;
  slips[0].second = Hold::normal;  // the sticking contact slips: its tangential row is free
  EXPECT_FALSE(kept.fits(slips, 1e-4, 1e-4, true));
  HeldRows opened = {same[0]};  // the second contact opened
  EXPECT_FALSE(kept.fits(opened, 1e-4, 1e-4, true));
  HeldRows other = same;
  other[1].first = key(5);  // another contact held
  EXPECT_FALSE(kept.fits(other, 1e-4, 1e-4, true));
  EXPECT_FALSE(kept.fits(same, 1e-2, 1e-4, true));  // a stiffer hold after a failed solve
}

TEST(KeptFactor, AProximalFactorIsKeptWhileTheRowsCannotHoldTheHub) {
  KeptFactor kept;
  KeptFactor::Made made;
  made.kind = KeptFactor::Kind::proximal;
  made.rows = {{key(3), Hold::normal}};
  made.hub_proximal = 1e-4;
  kept.record(made);
  kept.observe(1e-3, false, true);
  EXPECT_TRUE(kept.fits({{key(3), Hold::normal}, {key(4), Hold::normal}}, 1e-4, 1e-4, true));  // slipping rows
  EXPECT_FALSE(kept.fits({{key(3), Hold::stick}}, 1e-4, 1e-4, true));  // a sticking row would hold the hub
  EXPECT_FALSE(kept.fits({{key(3), Hold::normal}}, 1e-4, 1e-4, false));  // without a hub, any held row holds
  EXPECT_TRUE(kept.fits({}, 1e-4, 1e-4, false));
  EXPECT_FALSE(kept.fits({}, 1e-4, 1e-2, true));  // a stiffer hub after a failed solve
}

TEST(KeptFactor, IsDroppedAfterAKeptIterateThatContractsTooLittle) {
  KeptFactor kept;
  KeptFactor::Made made;  // K_z itself: fits any rows
  kept.record(made);
  kept.observe(1e-3, false, true);
  EXPECT_TRUE(kept.fits({}, 0.0, 0.0, false));
  kept.observe(0.9 * KeptFactor::kContraction * 1e-3, true, true);  // contracted enough
  EXPECT_TRUE(kept.fits({}, 0.0, 0.0, false));
  kept.observe(1e-3, true, true);  // grew again: refactor
  EXPECT_FALSE(kept.fits({}, 0.0, 0.0, false));
  kept.record(made);  // the iterate's own factor, then as before
  kept.observe(1e-4, false, true);
  EXPECT_TRUE(kept.fits({}, 0.0, 0.0, false));
}

TEST(KeptFactor, BoundsTheDistanceToTheFixedPointFromTheObservedContraction) {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  KeptFactor kept;
  kept.record(KeptFactor::Made{});
  kept.observe(1e-2, false, true);  // the iterate that made the factor: no contraction observed yet
  EXPECT_EQ(kept.distance_bound(), kNone);
  kept.observe(1e-3, true, true);  // its ratio to the Newton step is not the kept iteration's contraction
  EXPECT_EQ(kept.distance_bound(), kNone);
  kept.observe(1e-4, true, true);  // θ = 0.1: the rest of the iteration moves z by at most θ/(1 − θ) |Δz|
  EXPECT_DOUBLE_EQ(kept.distance_bound(), 0.1 / 0.9 * 1e-4);
  kept.observe(0.6e-4, true, true);  // θ = 0.6 > kContraction: the factor is about to be dropped, no bound
  EXPECT_EQ(kept.distance_bound(), kNone);
  kept.observe(1e-5, true, false);  // a relaxed step (z_{j+1} ≠ z_j + Δz_j) is another iteration
  EXPECT_EQ(kept.distance_bound(), kNone);
  kept.observe(1e-6, true, true);  // after a relaxed one: its |Δz| is not the same map's
  EXPECT_EQ(kept.distance_bound(), kNone);
  kept.observe(1e-7, true, true);
  EXPECT_DOUBLE_EQ(kept.distance_bound(), 0.1 / 0.9 * 1e-7);
  kept.record(KeptFactor::Made{});
  kept.observe(1e-8, false, true);  // a new factor's own iterate (the Newton step): no bound
  EXPECT_EQ(kept.distance_bound(), kNone);
  kept.observe(1e-9, true, true);
  kept.drop();
  kept.observe(1e-10, true, true);  // nothing kept since the step start
  EXPECT_EQ(kept.distance_bound(), kNone);
}

}  // namespace
}  // namespace csim
