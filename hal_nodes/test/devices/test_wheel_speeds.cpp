// Drive kinematics: body twist -> wheel speeds with curvature-preserving saturation,
// acceleration ramps and native-unit conversion.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hal_nodes/devices/drive/wheel_speeds.h"

using namespace hal_nodes;

TEST(WheelSpeeds, StraightAndTurn) {
  WheelSpeeds s = wheelSpeeds(0.5, 0.0, 0.3, 1.0);
  EXPECT_DOUBLE_EQ(s.left, 0.5);
  EXPECT_DOUBLE_EQ(s.right, 0.5);
  s = wheelSpeeds(0.0, 2.0, 0.3, 1.0);  // spin left: right wheel forward
  EXPECT_NEAR(s.left, -0.3, 1e-12);
  EXPECT_NEAR(s.right, 0.3, 1e-12);
}

TEST(WheelSpeeds, SaturationKeepsCurvature) {
  const WheelSpeeds s = wheelSpeeds(2.0, 2.0, 0.3, 1.0);  // wants 1.7 and 2.3 m/s
  EXPECT_NEAR(s.right, 1.0, 1e-12);
  EXPECT_NEAR(s.left / s.right, 1.7 / 2.3, 1e-12);
}

TEST(WheelSpeeds, NonFiniteCommandStops) {
  const WheelSpeeds s = wheelSpeeds(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.3, 1.0);
  EXPECT_EQ(s.left, 0.0);
  EXPECT_EQ(s.right, 0.0);
}

TEST(WheelSpeeds, RampLimitsAccelerationAndKeepsRatio) {
  WheelSpeeds cur;
  const WheelSpeeds target{0.5, 1.0};
  cur = rampTowards(cur, target, 1.0, 0.1);  // at most 0.1 m/s per wheel per step
  EXPECT_NEAR(cur.right, 0.1, 1e-12);
  EXPECT_NEAR(cur.left, 0.05, 1e-12);
  for (int i = 0; i < 20; ++i) cur = rampTowards(cur, target, 1.0, 0.1);
  EXPECT_DOUBLE_EQ(cur.left, 0.5);
  EXPECT_DOUBLE_EQ(cur.right, 1.0);
  EXPECT_DOUBLE_EQ(rampTowards(cur, WheelSpeeds(), 0.0, 0.1).left, 0.0);  // 0: no limit
}

TEST(WheelSpeeds, NativeUnitsRoundAndClamp) {
  EXPECT_EQ(nativeValue(0.5, 1000.0, 2000), 500);
  EXPECT_EQ(nativeValue(-0.5, -1000.0, 2000), 500);  // mirrored motor
  EXPECT_EQ(nativeValue(5.0, 1000.0, 2000), 2000);
  EXPECT_EQ(nativeValue(-5.0, 1000.0, 2000), -2000);
  EXPECT_EQ(nativeValue(0.00049, 1000.0, 2000), 0);
}
