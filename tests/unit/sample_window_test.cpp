#include <gtest/gtest.h>

#include "bushel/core/sample_window.hpp"

namespace bushel {
namespace {

TEST(SampleWindow, KeepsOneSampleAtOrBeforeTheWindowsStart) {
  SampleWindow w;
  for (int t = 0; t <= 10; ++t) w.add(t, 2.0 * t, 3.0);
  // The window is [7, 10]: 7 is the last sample at or before its start.
  ASSERT_EQ(w.time.size(), 4U);
  EXPECT_EQ(w.time.front(), 7.0);
  EXPECT_EQ(w.value.front(), 14.0);
}

TEST(SampleWindow, SlopeFollowsTheLatestRateOnly) {
  SampleWindow w;
  EXPECT_EQ(w.slope(), 0.0);  // no samples
  w.add(0.0, 0.0, 300.0);
  EXPECT_EQ(w.slope(), 0.0);  // one time only
  // 100 steps/s for an hour, then 40 steps/s: the average since the start would still be
  // 96 after five minutes; the window's slope is the new rate once the window has passed.
  double steps = 0.0;
  for (int t = 10; t <= 3600; t += 10) w.add(t, steps += 1000.0, 300.0);
  EXPECT_DOUBLE_EQ(w.slope(), 100.0);
  for (int t = 3610; t <= 3900; t += 10) w.add(t, steps += 400.0, 300.0);
  EXPECT_DOUBLE_EQ(w.slope(), 40.0);
}

}  // namespace
}  // namespace bushel
