// Contact like a table: only the part of a step that goes into an obstacle is cancelled. A round
// robot touching a round opponent turns in place both ways at the commanded rate; a robot meeting
// a wall at 10 degrees slides along it; pushed straight into a wall or the opponent it stops, its
// motors stalled and the bumper at the contact closed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "robot_sim/world/contact_solver.h"
#include "robot_sim/world/diff_drive.h"
#include "robot_sim/world/sim_world.h"
#include "world_test_support.h"

using namespace robot_sim;

namespace {
constexpr double kRadius = 0.16;

WorldConfig roundRobot(const Pose2D& start) {
  WorldConfig c;
  c.dt = 0.001;
  c.robot.start = start;
  c.robot.radius = kRadius;
  c.robot.wheel_radius = 0.035;
  c.robot.wheel_base = 0.25;
  addGripDriveMotors(c);
  EncoderConfig e;
  e.motor = "left";
  c.robot.encoders["left_driven"] = e;
  e.motor = "right";
  c.robot.encoders["right_driven"] = e;
  SwitchConfig b;
  b.type = "bumper";
  b.span = 0.8;
  for (const auto& [name, angle] : {std::pair<const char*, double>{"front_left", 0.4}, {"front_right", -0.4},
                                    {"side_left", M_PI / 2}, {"side_right", -M_PI / 2}}) {
    b.angle = angle;
    c.robot.switches[name] = b;
  }
  c.opponent.enabled = false;
  return c;
}

// The opponent parked touching our robot at `bearing` (base_link), 0.1 mm off.
WorldConfig againstOpponent(double bearing) {
  const Pose2D us{1.0, 1.05, 0.0};
  WorldConfig c = roundRobot(us);
  c.opponent.enabled = true;
  c.opponent.mode = "static";
  c.opponent.radius = kRadius;
  const double d = 2 * kRadius + 1e-4;
  c.opponent.start = Pose2D{us.x + d * std::cos(bearing), us.y + d * std::sin(bearing), M_PI};
  return c;
}

void drive(SimWorld& w, double left, double right, double seconds) {
  w.setMotorCommand("left", left);
  w.setMotorCommand("right", right);
  run(w, seconds);
}

// The yaw turned in `seconds` of a spin after 0.5 s of spin-up.
double spin(SimWorld& w, double command, double seconds) {
  drive(w, -command, command, 0.5);
  const double before = w.robotTruth().pose.theta;
  run(w, seconds);
  return wrapAngle(w.robotTruth().pose.theta - before);
}
}  // namespace

TEST(Contacts, ARoundRobotTouchingTheOpponentTurnsInPlaceBothWays) {
  // 48.5 degrees to the left: between the front and side bumpers, where a many-sided outline jammed.
  for (const double command : {0.3, -0.3}) {
    SimWorld free_world(roundRobot(Pose2D{1.0, 1.05, 0.0}), 1);
    const double commanded = spin(free_world, command, 0.5);
    SimWorld w(againstOpponent(48.5 * M_PI / 180.0), 1);
    const double turned = spin(w, command, 0.5);
    EXPECT_GT(std::abs(commanded), 0.5) << "the test's spin is too slow to tell";
    EXPECT_NEAR(turned, commanded, 1e-9) << "command " << command;
    EXPECT_NEAR(w.robotTruth().pose.x, 1.0, 1e-9);  // in place: not pushed off
    EXPECT_NEAR(w.robotTruth().pose.y, 1.05, 1e-9);
    EXPECT_GT(std::abs(w.motorCurrent("left")), 0.0);
    EXPECT_LT(std::abs(w.motorCurrent("left")), 0.5 * 6.0);  // turning, not stalled
  }
}

TEST(Contacts, ABoxRobotTurningIntoTheOpponentIsShovedAsideNotJammed) {
  WorldConfig c = againstOpponent(0.0);
  c.robot.footprint = {{0.10, 0.15}, {-0.20, 0.15}, {-0.20, -0.15}, {0.10, -0.15}};  // its front touches
  c.opponent.start.x = 1.0 + 0.10 + kRadius + 1e-4;
  SimWorld w(c, 1);
  const double turned = spin(w, 0.3, 0.5);
  EXPECT_GT(turned, 0.3);  // its corners swept round (jammed, it turned 0); the opponent's circle pushed it back
  const Contact touch = w.footprint().circleContact(w.robotTruth().pose, Circle{c.opponent.start.x, c.opponent.start.y, kRadius});
  EXPECT_GE(touch.clearance, -1e-6);
}

TEST(Contacts, ARobotMeetingAWallAtTenDegreesSlidesAlongIt) {
  const double angle = -10.0 * M_PI / 180.0;  // heading towards the y = 0 border
  SimWorld free_world(roundRobot(Pose2D{1.0, 1.0, angle}), 1);
  drive(free_world, 0.5, 0.5, 2.0);
  const double free_travel = std::hypot(free_world.robotTruth().pose.x - 1.0, free_world.robotTruth().pose.y - 1.0);
  SimWorld w(roundRobot(Pose2D{1.0, kRadius + 1e-4, angle}), 1);
  drive(w, 0.5, 0.5, 2.0);
  const Pose2D p = w.robotTruth().pose;
  EXPECT_NEAR(p.y, kRadius, 1e-6);  // along the wall, never into it
  // What is left after the part into the wall is cancelled: cos(10 deg) of the way along x.
  EXPECT_NEAR(p.x - 1.0, free_travel * std::cos(angle), 0.02 * free_travel);
  EXPECT_NEAR(p.theta, angle, 1e-9);
  EXPECT_TRUE(w.switchClosed("side_right"));  // touching the wall on its right
  EXPECT_GT(w.robotTruth().v, 0.9 * 0.5 * 20.0 * 0.035 * std::cos(angle) * std::cos(angle));
  EXPECT_GT(w.encoderTicks("left_driven"), 0);  // the wheels turn
}

TEST(Contacts, DrivenStraightIntoAWallOrTheOpponentItStopsStalledWithTheBumperClosed) {
  const MotorConfig motor = roundRobot(Pose2D{}).robot.motors.at("left");
  const double stalled = std::min(0.5 * motor.stall_current, motor.current_limit);  // at command 0.5, shaft held
  {
    SimWorld w(roundRobot(Pose2D{1.0, 2.1 - kRadius - 0.05, M_PI / 2}), 1);  // 5 cm from the y = 2.1 border
    drive(w, 0.5, 0.5, 2.0);
    const BodyTruth t = w.robotTruth();
    EXPECT_NEAR(t.pose.y, 2.1 - kRadius, 1e-6);
    EXPECT_NEAR(t.pose.x, 1.0, 1e-9);
    EXPECT_EQ(t.v, 0.0);
    EXPECT_NEAR(std::abs(w.motorCurrent("left")), stalled, 1e-6);
    const int64_t ticks = w.encoderTicks("left_driven");
    run(w, 0.5);
    EXPECT_EQ(w.encoderTicks("left_driven"), ticks);  // the wheel does not turn
    EXPECT_TRUE(w.switchClosed("front_left"));
    EXPECT_TRUE(w.switchClosed("front_right"));
  }
  {
    WorldConfig c = againstOpponent(0.0);
    c.opponent.start.x += 0.05;
    SimWorld w(c, 1);
    drive(w, 0.5, 0.5, 2.0);
    const BodyTruth t = w.robotTruth();
    EXPECT_NEAR(t.pose.x, c.opponent.start.x - 2 * kRadius, 1e-6);
    EXPECT_NEAR(t.pose.y, 1.05, 1e-9);
    EXPECT_EQ(t.v, 0.0);
    EXPECT_NEAR(std::abs(w.motorCurrent("right")), stalled, 1e-6);
    EXPECT_TRUE(w.switchClosed("front_left"));
    EXPECT_TRUE(w.switchClosed("front_right"));
    EXPECT_NEAR(w.opponentTruth().pose.x, c.opponent.start.x, 1e-12);  // a parked opponent is not pushed
  }
}

TEST(Contacts, WedgedInACornerItGoesNowhereButStillTurns) {
  SimWorld w(roundRobot(Pose2D{kRadius + 1e-4, kRadius + 1e-4, -3 * M_PI / 4}), 1);
  drive(w, 0.5, 0.5, 1.0);
  EXPECT_NEAR(w.robotTruth().pose.x, kRadius, 1e-4);
  EXPECT_NEAR(w.robotTruth().pose.y, kRadius, 1e-4);
  const double turned = spin(w, 0.3, 0.5);
  EXPECT_GT(turned, 0.5);
}

TEST(Contacts, TheSolverCancelsOnlyTheNormalPart) {
  const Footprint round = Footprint::circle(0.1);
  Obstacles table;
  table.table_length = 3.0;
  table.table_width = 2.0;
  // Touching x = 0, heading 120 degrees, 1 cm ahead: the -x part goes, the +y part stays, and
  // three quarters of the wheels' travel with it (no stall).
  const double h = 2.0 * M_PI / 3.0;
  const ResolvedMotion r = resolveMotion(round, Pose2D{0.1, 1.0, h},
                                         Pose2D{0.1 + 0.01 * std::cos(h), 1.0 + 0.01 * std::sin(h), h}, table, 0.25);
  EXPECT_NEAR(r.pose.x, 0.1, 1e-12);
  EXPECT_NEAR(r.pose.y, 1.0 + 0.01 * std::sin(h), 1e-12);
  EXPECT_TRUE(r.cancelled);
  EXPECT_FALSE(r.left_stalled || r.right_stalled);
  // An overlap already there may stay, never deepen; moving out of it is free.
  const ResolvedMotion out = resolveMotion(round, Pose2D{0.09, 1.0, 0.0}, Pose2D{0.095, 1.0, 0.0}, table, 0.25);
  EXPECT_FALSE(out.cancelled);
  const ResolvedMotion deeper = resolveMotion(round, Pose2D{0.09, 1.0, M_PI}, Pose2D{0.08, 1.0, M_PI}, table, 0.25);
  EXPECT_NEAR(deeper.pose.x, 0.09, 1e-12);
  EXPECT_TRUE(deeper.left_stalled && deeper.right_stalled);
}
