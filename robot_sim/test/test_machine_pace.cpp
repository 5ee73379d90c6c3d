// The pace of "as fast as the machine goes": the controller's steps for a measured busy share.
#include <gtest/gtest.h>

#include "../src/machine_pace.h"

using robot_sim::MachinePace;

TEST(MachinePace, FarFromBusyRisesInProportionCappedAtHalfAgain) {
  MachinePace pace(1.0);
  EXPECT_TRUE(pace.adjust(0.20));  // 0.85 / 0.20 = 4.25: capped
  EXPECT_DOUBLE_EQ(pace.factor(), 1.5);
  EXPECT_TRUE(pace.adjust(0.68));  // 0.85 / 0.68 = 1.25
  EXPECT_NEAR(pace.factor(), 1.5 * 1.25, 1e-9);
}

TEST(MachinePace, NearTheBandRisesByFifteenPercent) {
  MachinePace pace(2.0);
  EXPECT_TRUE(pace.adjust(0.79));
  EXPECT_NEAR(pace.factor(), 2.3, 1e-9);
}

TEST(MachinePace, InsideTheBandHolds) {
  MachinePace pace(2.0);
  EXPECT_FALSE(pace.adjust(0.85));
  EXPECT_DOUBLE_EQ(pace.factor(), 2.0);
}

TEST(MachinePace, SaturatedBacksOffWithinLimits) {
  MachinePace pace(0.28);
  EXPECT_TRUE(pace.adjust(0.99));
  EXPECT_DOUBLE_EQ(pace.factor(), 0.25);  // the floor
  EXPECT_FALSE(pace.adjust(0.99));
  MachinePace fast(40.0);
  fast.adjust(0.05);
  EXPECT_DOUBLE_EQ(fast.factor(), 50.0);  // the ceiling
}

TEST(MachinePace, ARobotLaggingBacksOffThoughTheMachineIsIdleButNotBelowRealTime) {
  MachinePace pace(4.0);
  EXPECT_TRUE(pace.adjust(0.40, /*robot_lagging=*/true));
  EXPECT_DOUBLE_EQ(pace.factor(), 3.4);
  MachinePace slow(1.1);
  slow.adjust(0.40, true);
  EXPECT_DOUBLE_EQ(slow.factor(), 1.0);
  slow.adjust(0.40, true);
  EXPECT_DOUBLE_EQ(slow.factor(), 1.0);
  slow.adjust(0.95, true);  // a saturated machine still goes below
  EXPECT_DOUBLE_EQ(slow.factor(), 0.85);
}

TEST(RobotKeepingUp, LagsWhenTheRequestRateInSimulatedTimeFalls) {
  using robot_sim::RobotKeepingUp;
  RobotKeepingUp robot;
  EXPECT_FALSE(robot.lagging(0, 0.0));       // first sample: nothing to compare
  EXPECT_FALSE(robot.lagging(230, 1.0));     // 230 requests per simulated second
  EXPECT_FALSE(robot.lagging(690, 3.0));     // the same rate over 2 s
  EXPECT_TRUE(robot.mayRise());
  EXPECT_TRUE(robot.lagging(1290, 7.0));     // 150 per second: behind
  EXPECT_NEAR(robot.rate(), 150.0, 1e-9);
  EXPECT_FALSE(robot.mayRise());
  // The reference decays: after a lasting lower rate (fewer boards), it is the new normal.
  bool lag = true;
  unsigned long polls = 1290;
  double t = 7.0;
  for (int i = 0; i < 60; ++i) lag = robot.lagging(polls += 150, t += 1.0);
  EXPECT_FALSE(lag);
}

TEST(RobotKeepingUp, AGradualDeclineIsCaught) {
  robot_sim::RobotKeepingUp robot;
  robot.lagging(0, 0.0);
  unsigned long polls = 0;
  double rate = 450.0, t = 0.0;
  bool lag = false;
  for (int i = 0; i < 10 && !lag; ++i) {
    lag = robot.lagging(polls += static_cast<unsigned long>(rate), t += 1.0);
    rate *= 0.96;  // 4 % less each second, as a loop falling behind a rising factor
  }
  EXPECT_TRUE(lag);
}

TEST(RobotKeepingUp, SettlesOnceTwoSecondsAgree) {
  robot_sim::RobotKeepingUp robot;
  robot.lagging(0, 0.0);
  robot.lagging(40, 1.0);  // boards coming up
  EXPECT_FALSE(robot.settled());
  robot.lagging(260, 2.0);
  EXPECT_FALSE(robot.settled());
  robot.lagging(490, 3.0);  // 230, then 230
  EXPECT_TRUE(robot.settled());
}

TEST(MachinePace, HoldsWhileItMayNotRise) {
  MachinePace pace(1.0);
  EXPECT_FALSE(pace.adjust(0.30, false, /*may_rise=*/false));
  EXPECT_DOUBLE_EQ(pace.factor(), 1.0);
  EXPECT_TRUE(pace.adjust(0.95, false, false));  // backing off needs no permission
}
