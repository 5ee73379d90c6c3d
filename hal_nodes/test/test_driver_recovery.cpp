// The driver's recoveries (driver/recovery.h), one per case: a back-off refused when the rear
// rangers see an obstacle and run to its distance when the rear is free, a stalled turn that goes
// the other way round to the same heading, a wait, the list used up, and an empty list.
#include <gtest/gtest.h>

#include <cmath>

#include "hal_nodes/driver/recovery.h"
#include "test_driver_support.h"

namespace hal_nodes {
namespace driver {
namespace {

RecoveryConfig threeSteps() {
  RecoveryConfig c;
  RecoveryStep back;
  back.kind = RecoveryStep::Kind::BACK_OFF;
  back.distance = 0.12;
  RecoveryStep turn;
  turn.kind = RecoveryStep::Kind::TURN_OTHER_WAY;
  RecoveryStep wait;
  wait.kind = RecoveryStep::Kind::WAIT;
  wait.duration = 1.5;
  c.steps = {back, turn, wait};
  c.rear_rangers = {"back"};
  c.rear_margin = 0.05;
  return c;
}

// Runs the started recovery on the kinematic model until it is over; returns the time it took.
double runToEnd(Recovery& r, KinematicModel& robot, double rear_free, double* turned = nullptr) {
  const double dt = 0.02;
  VelocityLimiter limiter(test::robotConfig().limits);
  double t = 0.0, theta = robot.pose().theta;
  for (; r.running() && t < 30.0; t += dt) {
    const Twist2D cmd = limiter.apply(r.step(robot.pose(), limiter.last(), t, rear_free), dt);
    robot.step(cmd, dt);
    if (turned) *turned += wrapAngle(robot.pose().theta - theta);
    theta = robot.pose().theta;
  }
  return t;
}
}  // namespace

TEST(Recovery, BackOffIsRefusedWhenTheRearRangersSeeAnObstacle) {
  Recovery r(threeSteps(), test::robotConfig());
  BlockedAt at;
  at.rear_free = 0.10;  // < 0.12 + 0.05
  at.turn_left = 0.0;   // not turning: turn_other_way does not apply either
  std::vector<std::string> skipped;
  ASSERT_TRUE(r.start(at, 0.0, &skipped));
  EXPECT_EQ(r.describe(), "wait (3 of 3)");
  ASSERT_EQ(skipped.size(), 2u);
  EXPECT_NE(skipped[0].find("rear not free (0.10 m"), std::string::npos) << skipped[0];
  EXPECT_NE(skipped[1].find("not turning"), std::string::npos);
  // Unknown (a stale ranger) is refused too.
  Recovery unknown(threeSteps(), test::robotConfig());
  at.rear_free = -1.0;
  skipped.clear();
  ASSERT_TRUE(unknown.start(at, 0.0, &skipped));
  EXPECT_NE(skipped[0].find("rear unknown"), std::string::npos);
}

TEST(Recovery, BackOffDrivesBackwardsItsDistanceWhereTheRearIsFree) {
  Recovery r(threeSteps(), test::robotConfig());
  KinematicModel robot({1.0, 1.0, 0.3});
  BlockedAt at;
  at.odom = robot.pose();
  at.rear_free = 0.8;
  ASSERT_TRUE(r.start(at, 0.0, nullptr));
  EXPECT_EQ(r.describe(), "back_off (1 of 3)");
  const double took = runToEnd(r, robot, 0.8);
  EXPECT_LT(took, 3.0);
  const double moved = (robot.pose().x - 1.0) * std::cos(0.3) + (robot.pose().y - 1.0) * std::sin(0.3);
  EXPECT_NEAR(moved, -0.12, 0.015);
  // Something comes within the margin behind: it stops short.
  Recovery again(threeSteps(), test::robotConfig());
  KinematicModel robot2({1.0, 1.0, 0.0});
  at.odom = robot2.pose();
  ASSERT_TRUE(again.start(at, 0.0, nullptr));
  runToEnd(again, robot2, 0.03);
  EXPECT_GT(robot2.pose().x, 1.0 - 0.05);
}

TEST(Recovery, AStalledTurnGoesTheOtherWayRoundToTheSameHeading) {
  RecoveryConfig c = threeSteps();
  c.steps.erase(c.steps.begin());  // turn_other_way first
  Recovery r(c, test::robotConfig());
  KinematicModel robot({1.0, 1.0, 0.0});
  BlockedAt at;
  at.odom = robot.pose();
  at.turn_left = 1.0;  // it was turning left to heading 1.0 when it stalled
  ASSERT_TRUE(r.start(at, 0.0, nullptr));
  EXPECT_EQ(r.describe(), "turn_other_way (1 of 2)");
  double turned = 0.0;
  runToEnd(r, robot, -1.0, &turned);
  EXPECT_NEAR(turned, 1.0 - 2.0 * M_PI, 0.06);             // clockwise, the long way round
  EXPECT_NEAR(wrapAngle(robot.pose().theta - 1.0), 0.0, 0.06);  // the same heading
  EXPECT_NEAR(robot.pose().x, 1.0, 1e-6);                   // in place
}

TEST(Recovery, AWaitStandsStillItsDurationThenTheListIsUsedUp) {
  RecoveryConfig c = threeSteps();
  c.steps = {c.steps[2]};
  Recovery r(c, test::robotConfig());
  BlockedAt at;
  ASSERT_TRUE(r.start(at, 10.0, nullptr));
  EXPECT_TRUE(r.running());
  Twist2D cmd = r.step(at.odom, Twist2D(), 11.0, -1.0);
  EXPECT_TRUE(r.running());
  EXPECT_EQ(cmd.v, 0.0);
  EXPECT_EQ(cmd.w, 0.0);
  r.step(at.odom, Twist2D(), 11.6, -1.0);
  EXPECT_FALSE(r.running());
  EXPECT_FALSE(r.start(at, 12.0, nullptr));  // each recovery once per goal
  EXPECT_EQ(r.tried(), "wait");
  r.reset();  // a new goal: the list again
  EXPECT_TRUE(r.start(at, 12.0, nullptr));
}

TEST(Recovery, AnEmptyListEndsAtOnce) {
  Recovery r(RecoveryConfig(), test::robotConfig());
  BlockedAt at;
  at.rear_free = 1.0;
  at.turn_left = 1.0;
  EXPECT_FALSE(r.start(at, 0.0, nullptr));
  EXPECT_FALSE(r.running());
  EXPECT_EQ(r.count(), 0u);
  EXPECT_EQ(r.tried(), "");
}

TEST(Recovery, TheRobotsConfigsAreReadAndBackOffNeedsRearRangers) {
  for (const char* robot : {"eurobot2009", "logion"}) {
    const RecoveryConfig c = readRecoveryConfig(
        robot_core::Params::fromYamlFile(std::string(ROBOT_CONFIG_DIR) + "/" + robot + ".yaml", "hal/driver"));
    EXPECT_FALSE(c.steps.empty()) << robot;
    EXPECT_FALSE(c.rear_rangers.empty()) << robot;
  }
  XmlRpc::XmlRpcValue tree;
  tree["recovery"]["behaviors"][0]["type"] = std::string("back_off");
  EXPECT_THROW(readRecoveryConfig(robot_core::Params(tree, "/hal/driver")), robot_core::ParameterError);
  tree["recovery"]["behaviors"][0]["type"] = std::string("spin");
  EXPECT_THROW(readRecoveryConfig(robot_core::Params(tree, "/hal/driver")), robot_core::ParameterError);
}

}  // namespace driver
}  // namespace hal_nodes
