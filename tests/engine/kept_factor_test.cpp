// Modified Newton's bookkeeping (engine/steppers/kept_factor.h): a later iterate keeps a step's factor only
// while the factor is a good model there (the same held rows and weights) and while it contracts.
#include "engine/steppers/kept_factor.h"

#include <gtest/gtest.h>

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
  kept.observe(1e-3, false);
  EXPECT_TRUE(kept.fits(held_factor().rows, 1e-4, 1e-4, true));
  kept.drop();
  EXPECT_FALSE(kept.fits(held_factor().rows, 1e-4, 1e-4, true));
}

TEST(KeptFactor, AHeldFactorIsDroppedWhenTheHeldRowsOrTheirWeightChange) {
  KeptFactor kept;
  kept.record(held_factor());
  kept.observe(1e-3, false);
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
  kept.observe(1e-3, false);
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
  kept.observe(1e-3, false);
  EXPECT_TRUE(kept.fits({}, 0.0, 0.0, false));
  kept.observe(0.9 * KeptFactor::kContraction * 1e-3, true);  // contracted enough
  EXPECT_TRUE(kept.fits({}, 0.0, 0.0, false));
  kept.observe(1e-3, true);  // grew again: refactor
  EXPECT_FALSE(kept.fits({}, 0.0, 0.0, false));
  kept.record(made);  // the iterate's own factor, then as before
  kept.observe(1e-4, false);
  EXPECT_TRUE(kept.fits({}, 0.0, 0.0, false));
}

}  // namespace
}  // namespace csim
