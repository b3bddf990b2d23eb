#include "tools/run/checks.h"

#include <gtest/gtest.h>

#include <cmath>

namespace csim {
namespace {

TEST(ExtremumTracker, ParabolaVertexIsExact) {
  // y = 3 - 2 (t - 0.4137)^2, sampled every 0.01 s: the vertex is recovered to round-off.
  ExtremumTracker tracker;
  for (int k = 0; k <= 100; ++k) {
    const double t = 0.01 * k;
    tracker.add(t, 3.0 - 2.0 * (t - 0.4137) * (t - 0.4137));
  }
  tracker.finish();
  ASSERT_EQ(tracker.extrema().size(), 1u);
  EXPECT_TRUE(tracker.extrema()[0].maximum);
  EXPECT_NEAR(tracker.extrema()[0].time, 0.4137, 1e-12);
  EXPECT_NEAR(tracker.extrema()[0].value, 3.0, 1e-12);
}

TEST(ExtremumTracker, SineHasAlternatingExtremaAndTheStartIsNotOne) {
  ExtremumTracker tracker;
  const double h = 1e-3;
  for (int k = 0; k <= 10000; ++k) tracker.add(k * h, std::cos(k * h));
  tracker.finish();
  const auto& e = tracker.extrema();
  ASSERT_EQ(e.size(), 3u);  // minima at pi, 3 pi, maximum at 2 pi
  EXPECT_FALSE(e[0].maximum);
  EXPECT_NEAR(e[0].time, M_PI, 1e-6);
  EXPECT_NEAR(e[0].value, -1.0, 1e-9);
  EXPECT_TRUE(e[1].maximum);
  EXPECT_NEAR(e[1].time, 2 * M_PI, 1e-6);
}

TEST(ExtremumTracker, RestAtTheEndIsAFinalExtremum) {
  ExtremumTracker tracker;
  for (int k = 0; k <= 10; ++k) tracker.add(k, k);  // rises
  for (int k = 11; k <= 20; ++k) tracker.add(k, 10);  // then sticks
  tracker.finish();
  ASSERT_EQ(tracker.extrema().size(), 1u);
  EXPECT_EQ(tracker.extrema()[0].value, 10);
  EXPECT_EQ(tracker.extrema()[0].time, 10);
}

TEST(ExtremumTracker, PlateauInsideAMonotoneMotionIsNotAnExtremum) {
  ExtremumTracker tracker;
  for (int k = 0; k <= 5; ++k) tracker.add(k, k);
  for (int k = 6; k <= 8; ++k) tracker.add(k, 5);      // stick
  for (int k = 9; k <= 12; ++k) tracker.add(k, k - 3);  // slips on, same direction
  tracker.finish();
  EXPECT_TRUE(tracker.extrema().empty());
}

TEST(ExtremumTracker, StickPlateauBetweenRiseAndFallIsOneExtremum) {
  ExtremumTracker tracker;
  for (int k = 0; k <= 5; ++k) tracker.add(k, k);
  for (int k = 6; k <= 8; ++k) tracker.add(k, 5);
  for (int k = 9; k <= 12; ++k) tracker.add(k, 13 - k);
  tracker.finish();
  ASSERT_EQ(tracker.extrema().size(), 1u);
  EXPECT_EQ(tracker.extrema()[0].value, 5);
  EXPECT_TRUE(tracker.extrema()[0].maximum);
}

}  // namespace
}  // namespace csim
