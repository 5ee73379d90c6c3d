// Tests of the whole world: a commanded straight run integrates to the expected pose and
// encoder counts, collisions stop the robot and close the right bumper, the same seed gives
// the same trajectory, faults act, the opponent follows its script, the match scores.
#include <gtest/gtest.h>

#include <cmath>

#include "robot_sim/world/diff_drive.h"
#include "robot_sim/world/motor_model.h"
#include "robot_sim/world/sim_world.h"
#include "world_test_support.h"

using namespace robot_sim;

namespace {
WorldConfig testConfig() {
  WorldConfig c;
  c.dt = 0.001;
  c.robot.start = Pose2D{0.5, 1.05, 0.0};
  c.robot.radius = 0.15;
  c.robot.wheel_radius = 0.035;
  c.robot.wheel_base = 0.25;
  addGripDriveMotors(c);
  EncoderConfig e;
  e.motor = "left";
  e.ticks_per_rev = 512;
  c.robot.encoders["left_driven"] = e;
  e.motor = "right";
  c.robot.encoders["right_driven"] = e;
  EncoderConfig f;
  f.y = 0.15;
  f.radius = 0.025;
  f.ticks_per_rev = 2000;
  c.robot.encoders["left_free"] = f;
  f.y = -0.15;
  c.robot.encoders["right_free"] = f;
  SwitchConfig b;
  b.type = "bumper";
  b.angle = 0.0;
  b.span = 1.2;
  c.robot.switches["bumper_front"] = b;
  b.angle = M_PI;
  c.robot.switches["bumper_back"] = b;
  c.opponent.enabled = false;
  c.table.beacons = {{-0.062, -0.062}, {-0.062, 2.162}, {3.062, 1.05}};
  return c;
}

}  // namespace

TEST(SimWorld, StraightRunIntegratesToExpectedPoseAndTicks) {
  const WorldConfig c = testConfig();
  SimWorld w(c, 1);
  w.setMotorCommand("left", 0.3);
  w.setMotorCommand("right", 0.3);
  // The expected travel: the same motor model integrated on its own.
  MotorState m;
  m.command = 0.3;
  double travel = 0.0;
  for (int i = 0; i < 2000; ++i) {
    stepMotor(c.robot.motors.at("left"), m, c.dt);
    travel += m.speed * c.robot.wheel_radius * c.dt;
  }
  run(w, 2.0);
  const BodyTruth t = w.robotTruth();
  EXPECT_NEAR(t.pose.x, 0.5 + travel, 1e-9);
  EXPECT_NEAR(t.pose.y, 1.05, 1e-12);
  EXPECT_NEAR(t.pose.theta, 0.0, 1e-12);
  EXPECT_NEAR(t.v, 0.3 * 20.0 * 0.035, 1e-6);  // steady state reached
  EXPECT_NEAR(travel, 0.21 * 2.0 - 0.21 * 0.05, 0.01);
  // No slip: driven and measuring wheels agree with the travel.
  const double driven = travel / (2 * M_PI * 0.035) * 512;
  const double free = travel / (2 * M_PI * 0.025) * 2000;
  EXPECT_NEAR(static_cast<double>(w.encoderTicks("left_driven")), driven, 1.0);
  EXPECT_NEAR(static_cast<double>(w.encoderTicks("right_driven")), driven, 1.0);
  EXPECT_NEAR(static_cast<double>(w.encoderTicks("left_free")), free, 1.0);
  EXPECT_NEAR(static_cast<double>(w.encoderTicks("right_free")), free, 1.0);
  EXPECT_NEAR(w.time(), 2.0, 1e-12);
}

TEST(SimWorld, UnknownNamesAreCountedNeverThrown) {
  SimWorld w(testConfig(), 1);
  EXPECT_TRUE(w.has("motor", "left"));
  EXPECT_FALSE(w.has("motor", "lft"));
  EXPECT_FALSE(w.has("gizmo", "left"));
  w.setMotorCommand("lft", 1.0);
  EXPECT_EQ(w.encoderTicks("nope"), 0);
  EXPECT_FALSE(w.switchClosed("nope"));
  EXPECT_TRUE(std::isinf(w.measureRange("nope")));
  EXPECT_EQ(w.encoderTicks(""), 0);  // "not connected": not counted
  EXPECT_EQ(w.unknownNameCount(), 4);
  const auto names = w.unknownNames();
  ASSERT_EQ(names.size(), 4u);
  EXPECT_EQ(names[1], "motor 'lft'");
}

TEST(SimWorld, TurnOnTheSpotMovesMeasuringWheelsOppositely) {
  SimWorld w(testConfig(), 1);
  w.setMotorCommand("left", -0.2);
  w.setMotorCommand("right", 0.2);
  run(w, 1.0);
  const BodyTruth t = w.robotTruth();
  EXPECT_NEAR(t.pose.x, 0.5, 1e-9);
  EXPECT_NEAR(t.pose.y, 1.05, 1e-9);
  EXPECT_GT(t.pose.theta, 0.5);  // counter-clockwise
  EXPECT_LT(w.encoderTicks("left_free"), 0);
  EXPECT_GT(w.encoderTicks("right_free"), 0);
  // Measuring wheels at +-0.15 m: arc = 0.15 * theta.
  const double arc_ticks = 0.15 * t.pose.theta / (2 * M_PI * 0.025) * 2000;
  EXPECT_NEAR(static_cast<double>(w.encoderTicks("right_free")), arc_ticks, 2.0);
}

TEST(SimWorld, SlipMakesDrivenEncodersOverCountDuringAcceleration) {
  WorldConfig c = testConfig();
  c.robot.slip.per_accel = 0.05;
  SimWorld w(c, 1);
  w.setMotorCommand("left", 0.8);
  w.setMotorCommand("right", 0.8);
  run(w, 0.3);  // still accelerating
  const double driven_m = w.encoderTicks("left_driven") / 512.0 * 2 * M_PI * 0.035;
  const double free_m = w.encoderTicks("left_free") / 2000.0 * 2 * M_PI * 0.025;
  EXPECT_GT(driven_m, free_m * 1.02);  // the wheel spun more than the ground moved
  EXPECT_NEAR(free_m, w.robotTruth().pose.x - 0.5, 0.001);
}

TEST(SimWorld, HittingABorderStopsTheRobotAndClosesTheFrontBumper) {
  WorldConfig c = testConfig();
  c.robot.start = Pose2D{2.5, 1.05, 0.0};
  SimWorld w(c, 1);
  EXPECT_FALSE(w.switchClosed("bumper_front"));
  w.setMotorCommand("left", 0.5);
  w.setMotorCommand("right", 0.5);
  run(w, 3.0);
  const BodyTruth t = w.robotTruth();
  EXPECT_NEAR(t.pose.x, 3.0 - 0.15, 0.01);
  EXPECT_LE(t.pose.x, 3.0 - 0.15 + 1e-9);
  EXPECT_EQ(t.v, 0.0);
  EXPECT_TRUE(w.switchClosed("bumper_front"));
  EXPECT_FALSE(w.switchClosed("bumper_back"));
  // Stalled: the current of a blocked shaft, 0.5 x 6 A, below the 4 A limit ...
  EXPECT_NEAR(w.motorCurrent("left"), 0.5 * c.robot.motors.at("left").stall_current, 1e-6);
  // ... and pushing harder hits the limiter.
  w.setMotorCommand("left", 0.9);
  w.setMotorCommand("right", 0.9);
  run(w, 0.1);
  EXPECT_NEAR(w.motorCurrent("left"), c.robot.motors.at("left").current_limit, 1e-6);
  EXPECT_LE(w.robotTruth().pose.x, 3.0 - 0.15 + 1e-9);
  // Backing off frees it.
  w.setMotorCommand("left", -0.5);
  w.setMotorCommand("right", -0.5);
  run(w, 0.5);
  EXPECT_LT(w.robotTruth().pose.x, 2.8);
  EXPECT_FALSE(w.switchClosed("bumper_front"));
}

TEST(SimWorld, TheOpponentBlocksAndIsSeenByARanger) {
  WorldConfig c = testConfig();
  c.opponent.enabled = true;
  c.opponent.mode = "static";
  c.opponent.start = Pose2D{1.5, 1.05, M_PI};
  RangerConfig r;
  r.mount = Pose2D{0.15, 0.0, 0.0};
  r.noise_std = 0.0;
  c.robot.rangers["front"] = r;
  SimWorld w(c, 1);
  EXPECT_NEAR(w.trueRange("front"), 1.5 - 0.15 - 0.5 - 0.15, 1e-9);
  EXPECT_NEAR(w.measureRange("front"), 0.7, 1e-9);
  w.setMotorCommand("left", 0.5);
  w.setMotorCommand("right", 0.5);
  run(w, 4.0);
  EXPECT_NEAR(w.robotTruth().pose.x, 1.5 - 0.3, 0.01);
  EXPECT_TRUE(w.switchClosed("bumper_front"));
  EXPECT_NEAR(w.opponentTruth().pose.x, 1.5, 1e-12);  // a static opponent is not pushed
}

TEST(SimWorld, SameSeedSameTrajectoryOtherSeedDiffers) {
  WorldConfig c = testConfig();
  c.robot.slip.per_accel = 0.02;
  c.robot.slip.noise_std = 0.01;
  c.opponent.enabled = true;
  c.opponent.mode = "random_walk";
  auto drive = [&](unsigned seed) {
    SimWorld w(c, seed);
    std::vector<double> trace;
    for (int k = 0; k < 6000; ++k) {
      if (k % 1000 == 0) {
        w.setMotorCommand("left", 0.2 + 0.1 * (k / 1000));
        w.setMotorCommand("right", 0.4 - 0.05 * (k / 1000));
      }
      // Sensor reads between steps must not change the trajectory.
      if (seed == 99 && k % 7 == 0) w.measureCompassDeg();
      w.step();
    }
    const BodyTruth t = w.robotTruth(), o = w.opponentTruth();
    return std::vector<double>{t.pose.x, t.pose.y, t.pose.theta, o.pose.x, o.pose.y};
  };
  const auto a = drive(42), b = drive(42), d = drive(43);
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << i;
  EXPECT_NE(a[0], d[0]);
  EXPECT_NE(a[3], d[3]);
}

TEST(SimWorld, FaultsSlipHardSilenceABeaconAndBlockThePath) {
  WorldConfig c = testConfig();
  c.opponent.enabled = true;
  c.opponent.mode = "static";
  c.beacons.dropout = 0.0;
  c.beacons.outlier = 0.0;
  SimWorld w(c, 1);
  std::string why;
  EXPECT_FALSE(w.applyFault("wheel_slip", "nope", true, 0.0, &why));
  EXPECT_NE(why.find("drive motor"), std::string::npos);
  ASSERT_TRUE(w.applyFault("wheel_slip", "left", true, 0.5, &why));
  w.setMotorCommand("left", 0.3);
  w.setMotorCommand("right", 0.3);
  run(w, 1.0);
  EXPECT_GT(w.robotTruth().pose.theta, 0.2);  // the slipping left wheel lags: the robot turns left
  ASSERT_TRUE(w.applyFault("wheel_slip", "left", false, 0.0, &why));

  ASSERT_TRUE(w.applyFault("beacon_silent", "2", true, 0.0, &why));
  w.takeBeaconMeasurements();
  run(w, 0.5);
  const auto m = w.takeBeaconMeasurements();
  EXPECT_FALSE(m.empty());
  for (const auto& b : m) EXPECT_NE(b.beacon_id, 2);
  EXPECT_FALSE(w.applyFault("beacon_silent", "7", true, 0.0, &why));

  ASSERT_TRUE(w.applyFault("opponent_blocks", "", true, 0.1, &why));
  w.step();
  const BodyTruth us = w.robotTruth(), them = w.opponentTruth();
  const double gap = std::hypot(them.pose.x - us.pose.x, them.pose.y - us.pose.y) - 0.3;
  EXPECT_NEAR(gap, 0.1, 0.01);
  EXPECT_NEAR(std::atan2(them.pose.y - us.pose.y, them.pose.x - us.pose.x), us.pose.theta, 0.02);
}

TEST(SimWorld, ScriptedOpponentVisitsItsWaypoints) {
  WorldConfig c = testConfig();
  c.opponent.enabled = true;
  c.opponent.mode = "script";
  c.opponent.start = Pose2D{2.5, 0.5, 0.0};
  c.opponent.speed = 0.5;
  c.opponent.pause = 0.5;
  c.opponent.waypoints = {{2.5, 1.5}, {1.5, 1.5}};
  SimWorld w(c, 1);
  bool at_first = false, at_second = false;
  for (int k = 0; k < 12000; ++k) {
    w.step();
    const Pose2D p = w.opponentTruth().pose;
    at_first |= std::hypot(p.x - 2.5, p.y - 1.5) < 0.02;
    at_second |= at_first && std::hypot(p.x - 1.5, p.y - 1.5) < 0.02;
  }
  EXPECT_TRUE(at_first);
  EXPECT_TRUE(at_second);
}

TEST(SimWorld, ScheduledCommandsApplyAtTheirExactStep) {
  SimWorld a(testConfig(), 1), b(testConfig(), 1);
  a.scheduleMotorCommand(0.5, "left", 0.4);
  a.scheduleMotorCommand(0.5, "right", 0.4);
  for (int k = 0; k < 1500; ++k) {
    if (k == 499) {  // step 500 ends at t = 0.5: the command is applied at its start
      b.setMotorCommand("left", 0.4);
      b.setMotorCommand("right", 0.4);
    }
    a.step();
    b.step();
  }
  EXPECT_EQ(a.robotTruth().pose.x, b.robotTruth().pose.x);
  EXPECT_GT(a.robotTruth().pose.x, 0.6);
}

TEST(SimWorld, CollectorSwallowsAndEjectsAndMatchScores) {
  WorldConfig c = testConfig();
  MotorConfig roller;
  c.robot.motors["roller"] = roller;
  CollectorConfig col;
  col.x = 0.15;
  col.radius = 0.05;
  col.motor = "roller";
  col.kinds = {"ball_red"};
  c.robot.collectors["harvester"] = col;
  GameElement ball;
  ball.kind = "ball_red";
  ball.radius = 0.035;
  ball.pose = Pose2D{0.9, 1.05, 0.0};
  c.table.elements = {ball};
  Zone z;
  z.x0 = 1.3;
  z.x1 = 1.6;
  z.y0 = 0.9;
  z.y1 = 1.2;
  z.points = 3;
  c.table.score_zones = {z};
  SwitchConfig cord;
  cord.type = "manual";
  cord.initially_closed = true;
  c.robot.switches["start_cord"] = cord;
  c.match.start_switch = "start_cord";
  c.match.duration = 90.0;
  SimWorld w(c, 1);
  run(w, 0.1);
  EXPECT_FALSE(w.match().started);
  ASSERT_TRUE(w.setSwitch("start_cord", false));
  EXPECT_FALSE(w.setSwitch("bumper_front", true));  // not a manual switch
  w.setMotorCommand("roller", 0.5);
  w.setMotorCommand("left", 0.3);
  w.setMotorCommand("right", 0.3);
  run(w, 1.2);
  EXPECT_TRUE(w.match().started);
  EXPECT_TRUE(w.elements()[0].carried);
  // Drive on so the mouth is inside the zone, stop and eject.
  while (w.robotTruth().pose.x < 1.2) w.step();
  w.setMotorCommand("left", 0.0);
  w.setMotorCommand("right", 0.0);
  run(w, 0.5);
  w.setMotorCommand("roller", -0.5);
  run(w, 0.3);
  EXPECT_FALSE(w.elements()[0].carried);
  EXPECT_EQ(w.match().score_ours, 3);
  EXPECT_EQ(w.match().score_opponent, 0);
  EXPECT_FALSE(w.match().over);
}

// The 2009 hand: fingers closing on a column at the mouth carry it; opening puts it down at
// the mouth.
TEST(SimWorld, GripperTakesCarriesAndReleasesAtTheMouth) {
  WorldConfig c = testConfig();
  ServoConfig finger;
  finger.min = -1.2;
  finger.max = 1.2;
  finger.speed = 4.0;
  finger.initial = 0.0;
  c.robot.servos["hand_left"] = finger;
  c.robot.servos["hand_right"] = finger;
  CollectorConfig hand;
  hand.x = 0.17;
  hand.radius = 0.05;
  hand.capacity = 1;
  hand.kinds = {"column_red"};
  hand.fingers = {"hand_left", "hand_right"};
  hand.finger_closed = {0.94, -0.94};
  c.robot.collectors["hand"] = hand;
  GameElement column;
  column.kind = "column_red";
  column.radius = 0.035;
  column.pose = Pose2D{0.5 + 0.17, 1.05, 0.0};  // at the mouth of the robot at (0.5, 1.05)
  GameElement other = column;
  other.pose = Pose2D{1.5, 1.05, 0.0};
  c.table.elements = {column, other};
  SimWorld w(c, 1);
  // One finger closed: no grip.
  w.setServoTarget("hand_left", 0.94);
  run(w, 0.6);
  EXPECT_FALSE(w.elements()[0].carried);
  w.setServoTarget("hand_right", -0.94);
  run(w, 0.6);
  ASSERT_TRUE(w.elements()[0].carried);
  EXPECT_FALSE(w.elements()[1].carried);
  // Turn on the spot by 90 degrees, open: the column stands at the mouth, (0.5, 1.22).
  w.setMotorCommand("left", -0.2);
  w.setMotorCommand("right", 0.2);
  while (w.robotTruth().pose.theta < M_PI / 2) w.step();
  w.setMotorCommand("left", 0.0);
  w.setMotorCommand("right", 0.0);
  run(w, 0.5);
  EXPECT_TRUE(w.elements()[0].carried);
  w.setServoTarget("hand_left", -1.2);
  run(w, 0.6);
  const auto put = w.elements()[0];
  EXPECT_FALSE(put.carried);
  const Pose2D r = w.robotTruth().pose;
  // Put down ahead of the robot, at the mouth or just outside the body that pushes it.
  const double d = std::hypot(put.pose.x - r.x, put.pose.y - r.y);
  EXPECT_GE(d, 0.17 - 1e-6);
  EXPECT_LE(d, c.robot.radius + column.radius + 1e-6);
  EXPECT_NEAR(std::atan2(put.pose.y - r.y, put.pose.x - r.x), r.theta, 1e-3);
  EXPECT_GT(put.pose.y, 1.15);
  EXPECT_FALSE(w.elements()[1].carried);
}
