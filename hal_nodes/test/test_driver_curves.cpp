// The Autopilot's control curves and the velocity limiter.
#include <gtest/gtest.h>

#include <cmath>

#include "hal_nodes/driver/control_curves.h"
#include "hal_nodes/driver/motion_limits.h"

using namespace hal_nodes::driver;

TEST(ControlCurve, ZeroAtZeroSaturatesAndIsOdd) {
  const ControlCurve c{0.3, 0.7};
  EXPECT_EQ(c.fraction(0.0), 0.0);
  EXPECT_DOUBLE_EQ(c.fraction(0.3), 1.0);
  EXPECT_DOUBLE_EQ(c.fraction(5.0), 1.0);
  EXPECT_DOUBLE_EQ(c.fraction(-5.0), -1.0);
  EXPECT_DOUBLE_EQ(c.fraction(-0.1), -c.fraction(0.1));
  EXPECT_EQ(c.fraction(std::nan("")), 0.0);
}

TEST(ControlCurve, TwoParametersSetTheShape) {
  const ControlCurve linear{0.4, 1.0}, soft{0.4, 2.0}, hard{0.4, 0.5};
  EXPECT_NEAR(linear.fraction(0.1), 0.25, 1e-12);
  EXPECT_NEAR(soft.fraction(0.1), 0.0625, 1e-12);
  EXPECT_NEAR(hard.fraction(0.1), 0.5, 1e-12);
  // Monotonic: slows down all the way in, never speeds up closer to the goal.
  for (const auto& c : {linear, soft, hard}) {
    double prev = 0.0;
    for (double e = 0.001; e < 1.0; e += 0.001) {
      const double f = c.fraction(e);
      EXPECT_GE(f, prev);
      prev = f;
    }
  }
}

TEST(ControlCurve, RejectsBadParameters) {
  EXPECT_TRUE(ControlCurve({0.3, 1.0}).invalidReason().empty());
  EXPECT_FALSE(ControlCurve({0.0, 1.0}).invalidReason().empty());
  EXPECT_FALSE(ControlCurve({0.3, 0.0}).invalidReason().empty());
  EXPECT_FALSE(ControlCurve({0.3, 9.0}).invalidReason().empty());
}

TEST(ControlCurve, BrakingSpeedStopsInTheRemainingDistance) {
  const double v = brakingSpeed(0.125, 1.0);
  EXPECT_NEAR(v * v / (2 * 1.0), 0.125, 1e-12);
  EXPECT_EQ(brakingSpeed(-1.0, 1.0), 0.0);
}

namespace {
MotionLimits limits() {
  MotionLimits l;
  l.max_linear_speed = 0.5;
  l.max_angular_speed = 3.0;
  l.max_linear_accel = 1.0;
  l.max_angular_accel = 6.0;
  l.max_wheel_speed = 0.6;
  l.track_width = 0.3;
  return l;
}
}  // namespace

TEST(VelocityLimiter, NeverExceedsSpeedOrAcceleration) {
  VelocityLimiter lim(limits());
  const double dt = 0.02;
  Twist2D prev;
  // A hostile sequence: jumps, sign flips, huge values, NaN.
  const Twist2D asks[] = {{10, 0}, {-10, 50}, {0.3, -2}, {std::nan(""), 1}, {0, 0}, {0.5, 3}, {-0.5, -3}};
  for (int k = 0; k < 200; ++k) {
    const Twist2D out = lim.apply(asks[k % 7], dt);
    EXPECT_LE(std::fabs(out.v), 0.5 + 1e-12);
    EXPECT_LE(std::fabs(out.w), 3.0 + 1e-12);
    EXPECT_LE(std::fabs(out.v) + std::fabs(out.w) * 0.15, 0.6 + 1e-12);
    EXPECT_LE(std::fabs(out.v - prev.v), 1.0 * dt + 1e-12);
    EXPECT_LE(std::fabs(out.w - prev.w), 6.0 * dt + 1e-12);
    EXPECT_TRUE(std::isfinite(out.v) && std::isfinite(out.w));
    prev = out;
  }
}

TEST(VelocityLimiter, WheelLimitKeepsTheCurvature) {
  VelocityLimiter lim(limits());
  const Twist2D c = lim.clampSpeed({0.5, 2.0});  // outer wheel 0.8 m/s asked
  EXPECT_NEAR(std::fabs(c.v) + std::fabs(c.w) * 0.15, 0.6, 1e-12);
  EXPECT_NEAR(c.w / c.v, 2.0 / 0.5, 1e-12);
}

TEST(VelocityLimiter, RampsUpAndStopsOnResetAtOnce) {
  VelocityLimiter lim(limits());
  for (int i = 0; i < 100; ++i) lim.apply({0.4, 0.0}, 0.02);
  EXPECT_NEAR(lim.last().v, 0.4, 1e-12);
  // A controlled stop ramps down...
  EXPECT_NEAR(lim.apply({0.0, 0.0}, 0.02).v, 0.38, 1e-12);
  // ...the emergency stop does not.
  lim.reset();
  EXPECT_EQ(lim.last().v, 0.0);
  EXPECT_EQ(lim.apply({0.0, 0.0}, 0.02).v, 0.0);
}

TEST(MotionLimits, RejectsNonPositive) {
  MotionLimits l = limits();
  EXPECT_TRUE(l.invalidReason().empty());
  l.max_linear_accel = 0.0;
  EXPECT_NE(l.invalidReason().find("max_linear_accel"), std::string::npos);
}
