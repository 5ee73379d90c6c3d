// The published estimate carried forward to the newest odometry: it lands where the filter
// would have put the robot after the same motion, and an odometry that arrives late does
// not move it back.
#include <gtest/gtest.h>

#include <cmath>

#include "../src/devices/localization/carried_pose.h"

using hal_nodes::localization::carryForward;
using hal_nodes::localization::NewestOdometry;
using hal_nodes::mcl::Pose2D;

TEST(CarriedPose, NoMotionLeavesTheEstimate) {
  const Pose2D est{1.2, 0.4, 0.7}, odom{3.0, -2.0, -1.1};
  const Pose2D p = carryForward(est, odom, odom);
  EXPECT_NEAR(p.x, est.x, 1e-12);
  EXPECT_NEAR(p.y, est.y, 1e-12);
  EXPECT_NEAR(p.theta, est.theta, 1e-12);
}

TEST(CarriedPose, MotionIsAppliedInTheRobotsFrame) {
  // The odometry frame is rotated against the map (its drift): 10 cm forward and a 0.1 rad turn
  // in odometry are 10 cm along the estimate's own heading in the map.
  const Pose2D est{1.0, 1.0, M_PI / 2};
  const Pose2D odom0{0.5, 0.0, 0.0}, odom1{0.6, 0.0, 0.1};
  const Pose2D p = carryForward(est, odom0, odom1);
  EXPECT_NEAR(p.x, 1.0, 1e-9);
  EXPECT_NEAR(p.y, 1.1, 1e-9);
  EXPECT_NEAR(p.theta, M_PI / 2 + 0.1, 1e-9);
}

TEST(CarriedPose, TurningInPlaceCarriesTheHeading) {
  // 50 ms of a 3 rad/s turn: the estimate it replaces was 0.15 rad behind.
  const Pose2D est{0.3, 0.2, 3.1}, odom0{0.0, 0.0, 3.0}, odom1{0.0, 0.0, 3.15};
  const Pose2D p = carryForward(est, odom0, odom1);
  EXPECT_NEAR(p.x, 0.3, 1e-9);
  EXPECT_NEAR(p.y, 0.2, 1e-9);
  EXPECT_NEAR(std::remainder(p.theta - 3.25, 2 * M_PI), 0.0, 1e-9);
}

TEST(NewestOdometry, KeepsTheNewestByStampWhateverTheArrivalOrder) {
  NewestOdometry n;
  EXPECT_FALSE(n.have());
  n.offer(2.0, {2, 0, 0});
  n.offer(1.0, {1, 0, 0});  // late
  EXPECT_TRUE(n.have());
  EXPECT_DOUBLE_EQ(n.stamp(), 2.0);
  EXPECT_DOUBLE_EQ(n.pose().x, 2.0);
  n.offer(3.0, {3, 0, 0});
  EXPECT_DOUBLE_EQ(n.stamp(), 3.0);
  EXPECT_DOUBLE_EQ(n.pose().x, 3.0);
}
