#include <gtest/gtest.h>

#include "robot_core/rate_meter.h"

using robot_core::RateMeter;

TEST(RateMeter, SteadyLoopGivesItsRate) {
  RateMeter m(1.0);
  for (int i = 0; i <= 200; ++i) m.tick(i * 0.01, 0.001);
  EXPECT_NEAR(m.rate(), 100.0, 1e-6);
  EXPECT_NEAR(m.maxPeriodError(0.01), 0.0, 1e-9);
  EXPECT_NEAR(m.meanBusy(), 0.001, 1e-12);
}

TEST(RateMeter, WindowForgetsOldTicks) {
  RateMeter m(1.0);
  for (int i = 0; i <= 100; ++i) m.tick(i * 0.01);        // 100 Hz for 1 s
  for (int i = 1; i <= 40; ++i) m.tick(1.0 + i * 0.05);  // then 20 Hz for 2 s
  EXPECT_NEAR(m.rate(), 20.0, 1e-6);
}

TEST(RateMeter, JitterAndBusyAreMeasured) {
  RateMeter m(10.0);
  m.tick(0.0, 0.002);
  m.tick(0.010, 0.004);
  m.tick(0.025, 0.001);  // one period 5 ms late
  EXPECT_NEAR(m.maxPeriodError(0.01), 0.005, 1e-9);
  EXPECT_NEAR(m.maxBusy(), 0.004, 1e-12);
}

TEST(RateMeter, TooFewTicksHaveNoRate) {
  RateMeter m;
  EXPECT_EQ(m.rate(), 0.0);
  m.tick(1.0);
  EXPECT_EQ(m.rate(), 0.0);
}
