#include <gtest/gtest.h>

#include <cmath>

#include "robot_core/geometry.h"

using robot_core::wrapAngle;
using robot_core::yawFromQuaternion;

TEST(Geometry, WrapAngleIsInMinusPiExclusivePiInclusive) {
  EXPECT_DOUBLE_EQ(wrapAngle(0.5), 0.5);
  EXPECT_DOUBLE_EQ(wrapAngle(M_PI), M_PI);
  EXPECT_DOUBLE_EQ(wrapAngle(-M_PI), M_PI);
  EXPECT_NEAR(wrapAngle(3 * M_PI / 2), -M_PI / 2, 1e-12);
  EXPECT_NEAR(wrapAngle(-3 * M_PI / 2), M_PI / 2, 1e-12);
  EXPECT_NEAR(wrapAngle(20 * M_PI + 0.25), 0.25, 1e-12);
  for (double a = -50.0; a < 50.0; a += 0.37) {
    const double w = wrapAngle(a);
    EXPECT_GT(w, -M_PI);
    EXPECT_LE(w, M_PI);
    EXPECT_NEAR(std::remainder(w - a, 2 * M_PI), 0.0, 1e-9);
  }
}

TEST(Geometry, YawFromQuaternion) {
  for (double yaw : {0.0, 0.3, -1.2, 3.0, -3.1}) {
    EXPECT_NEAR(yawFromQuaternion(0, 0, std::sin(yaw / 2), std::cos(yaw / 2)), yaw, 1e-12);
  }
  // the same heading with a roll (a robot on a slope), q = q_yaw * q_roll: the yaw stays
  const double yaw = 0.7, roll = 0.1;
  const double cy = std::cos(yaw / 2), sy = std::sin(yaw / 2), cr = std::cos(roll / 2), sr = std::sin(roll / 2);
  EXPECT_NEAR(yawFromQuaternion(cy * sr, sy * sr, cr * sy, cr * cy), yaw, 1e-12);
}
