// The robot's outline as a polygon: its checks, contacts with borders and circles, pushing, and
// in the whole world: where a non-circular robot stops against a border and the opponent,
// which bumper a corner contact closes, and how a flat front pushes a column.
#include <gtest/gtest.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <cmath>

#include "robot_sim/world/footprint.h"
#include "robot_sim/world/sim_world.h"

using namespace robot_sim;

namespace {
// Front at +0.10, back at -0.20, sides at +-0.15: no circle about base_link fits it.
std::vector<Point2D> box(double front, double back, double half_width) {
  return {{front, half_width}, {back, half_width}, {back, -half_width}, {front, -half_width}};
}

WorldConfig boxRobot() {
  WorldConfig c;
  c.dt = 0.001;
  c.robot.start = Pose2D{1.0, 1.05, 0.0};
  c.robot.radius = 0.15;
  c.robot.footprint = box(0.10, -0.20, 0.15);
  c.robot.wheel_base = 0.25;
  MotorConfig m;
  m.drive = "left";
  c.robot.motors["left"] = m;
  m.drive = "right";
  c.robot.motors["right"] = m;
  SwitchConfig b;
  b.type = "bumper";
  b.span = 0.8;
  b.angle = 0.4;
  c.robot.switches["front_left"] = b;
  b.angle = -0.4;
  c.robot.switches["front_right"] = b;
  b.angle = -M_PI / 2;
  b.span = 1.0;
  c.robot.switches["side_right"] = b;
  b.angle = M_PI;
  b.span = 1.2;
  c.robot.switches["back"] = b;
  c.robot.slip.per_accel = 0.0;
  c.robot.slip.noise_std = 0.0;
  c.opponent.enabled = false;
  return c;
}

void drive(SimWorld& w, double left, double right, double seconds) {
  w.setMotorCommand("left", left);
  w.setMotorCommand("right", right);
  for (long i = 0, n = std::lround(seconds / w.dt()); i < n; ++i) w.step();
}
}  // namespace

TEST(Footprint, RejectsWhatIsNotAnOutline) {
  EXPECT_THROW(Footprint({{0.1, 0.0}, {0.0, 0.1}}), ConfigError);                        // 2 vertices
  EXPECT_THROW(Footprint({{0.1, 0.1}, {-0.1, -0.1}, {0.1, -0.1}, {-0.1, 0.1}}), ConfigError);  // a bow tie
  EXPECT_THROW(Footprint({{0.3, 0.1}, {0.2, 0.1}, {0.2, -0.1}, {0.3, -0.1}}), ConfigError);    // origin outside
  const Footprint f(box(0.10, -0.20, 0.15));
  EXPECT_NEAR(f.reach(0.0), 0.10, 1e-12);
  EXPECT_NEAR(f.reach(M_PI), 0.20, 1e-12);
  EXPECT_NEAR(f.boundingRadius(), std::hypot(0.20, 0.15), 1e-12);
  // The default: 32 vertices on the radius, one at the front.
  const auto reg = Footprint::regular(0.16, 32);
  ASSERT_EQ(reg.size(), 32u);
  EXPECT_NEAR(reg[0].x, 0.16, 1e-12);
  EXPECT_NEAR(Footprint(reg).reach(M_PI / 2), 0.16, 1e-12);
}

TEST(Footprint, BorderAndCircleContacts) {
  // The box at (1, 1) turned by 90 degrees: its front (+0.10) faces +y.
  const Footprint f(box(0.10, -0.20, 0.15));
  const auto poly = f.placed(Pose2D{1.0, 1.0, M_PI / 2});
  Contact b = f.borderContact(Pose2D{1.0, 1.0, M_PI / 2}, 3.0, 1.2);
  EXPECT_NEAR(b.clearance, 1.2 - 1.1, 1e-12);
  EXPECT_NEAR(b.normal.y, 1.0, 1e-12);
  EXPECT_NEAR(b.point.x, 1.0, 1e-12);  // a flat side touches at its middle
  EXPECT_NEAR(b.point.y, 1.1, 1e-12);
  // A circle outside, ahead of the front, and one whose centre is inside.
  Contact o = circleContact(poly, Circle{1.05, 1.3, 0.05});
  EXPECT_NEAR(o.clearance, 0.2 - 0.05, 1e-12);
  EXPECT_NEAR(o.point.x, 1.05, 1e-12);
  EXPECT_NEAR(o.point.y, 1.1, 1e-12);
  Contact in = circleContact(poly, Circle{1.0, 1.08, 0.03});
  EXPECT_NEAR(in.clearance, -0.02 - 0.03, 1e-12);
  EXPECT_NEAR(in.normal.y, 1.0, 1e-12);
  Circle c{1.0, 1.08, 0.03};
  ASSERT_TRUE(pushOut(poly, c));
  EXPECT_NEAR(c.x, 1.0, 1e-12);
  EXPECT_NEAR(c.y, 1.1 + 0.03, 1e-12);
  EXPECT_FALSE(pushOut(poly, c));
}

TEST(Footprint, ConfigReadsTheOutlineAndNamesTheParameter) {
  XmlRpc::XmlRpcValue world, table;
  world["robot"]["motors"]["left"]["drive"] = std::string("left");
  world["robot"]["motors"]["right"]["drive"] = std::string("right");
  const std::vector<Point2D> want = box(0.10, -0.20, 0.15);
  for (int i = 0; i < 4; ++i) {
    world["robot"]["footprint"][i][0] = want[i].x;
    world["robot"]["footprint"][i][1] = want[i].y;
  }
  const WorldConfig c = parseWorldConfig(world, "/sim/world", table, "/table");
  ASSERT_EQ(c.robot.footprint.size(), 4u);
  EXPECT_DOUBLE_EQ(c.robot.footprint[1].x, -0.20);
  world["robot"]["footprint"][1][0] = 0.5;  // the box moved ahead of base_link: origin outside
  world["robot"]["footprint"][2][0] = 0.5;
  try {
    parseWorldConfig(world, "/sim/world", table, "/table");
    FAIL() << "an outline missing base_link's origin accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/sim/world/robot/footprint"), std::string::npos) << e.what();
  }
  world["robot"]["footprint"] = 0.3;
  EXPECT_THROW(parseWorldConfig(world, "/sim/world", table, "/table"), ConfigError);
}

TEST(Footprint, TheOutlineStopsTheRobotAtBorderAndOpponent) {
  WorldConfig c = boxRobot();
  c.robot.start = Pose2D{2.5, 1.05, 0.0};
  {
    SimWorld w(c, 1);
    drive(w, 0.5, 0.5, 3.0);
    EXPECT_NEAR(w.robotTruth().pose.x, 3.0 - 0.10, 0.01);  // the front, not a 0.15 radius
    EXPECT_LE(w.robotTruth().pose.x, 3.0 - 0.10 + 1e-9);
    EXPECT_TRUE(w.switchClosed("front_left"));  // square on: the middle of the front, both
    EXPECT_TRUE(w.switchClosed("front_right"));
    EXPECT_FALSE(w.switchClosed("back"));
    drive(w, -0.5, -0.5, 12.0);  // reversing to the far border: the back is 0.20 long
    EXPECT_NEAR(w.robotTruth().pose.x, 0.20, 0.01);
    EXPECT_GE(w.robotTruth().pose.x, 0.20 - 1e-9);
    EXPECT_TRUE(w.switchClosed("back"));
    EXPECT_FALSE(w.switchClosed("front_left"));
  }
  c.robot.start = Pose2D{0.8, 1.05, 0.0};
  c.opponent.enabled = true;
  c.opponent.mode = "static";
  c.opponent.start = Pose2D{1.5, 1.05, M_PI};
  c.opponent.radius = 0.15;
  SimWorld w(c, 1);
  drive(w, 0.5, 0.5, 4.0);
  EXPECT_NEAR(w.robotTruth().pose.x, 1.5 - 0.15 - 0.10, 0.01);
  EXPECT_TRUE(w.switchClosed("front_left"));
}

TEST(Footprint, ACornerContactClosesTheBumperAtThatCorner) {
  // A wide robot (0.40 across, 0.20 deep) heading 0.6 rad towards the x = 3 border: its front
  // right corner (0.10, -0.20), 63 degrees right of ahead, touches first. A circle would have
  // touched 34 degrees right of ahead (the border's normal), the front right bumper.
  WorldConfig c = boxRobot();
  c.robot.footprint = box(0.10, -0.10, 0.20);
  c.robot.start = Pose2D{2.5, 1.05, 0.6};
  SimWorld w(c, 1);
  const double corner_x = 0.10 * std::cos(0.6) + 0.20 * std::sin(0.6);
  drive(w, 0.4, 0.4, 4.0);
  const Pose2D p = w.robotTruth().pose;
  EXPECT_NEAR(p.x + corner_x, 3.0, 0.01);
  EXPECT_LE(p.x + corner_x, 3.0 + 1e-9);
  EXPECT_TRUE(w.switchClosed("side_right"));
  EXPECT_FALSE(w.switchClosed("front_right"));
  EXPECT_FALSE(w.switchClosed("front_left"));
}

TEST(Footprint, AFlatFrontPushesAColumnStraightAhead) {
  WorldConfig c = boxRobot();
  GameElement column;
  column.kind = "column_red";
  column.radius = 0.035;
  column.pose = Pose2D{1.0 + 0.10 + 0.05, 1.05 + 0.08, 0.0};  // 8 cm left of the centre line
  c.table.elements = {column};
  SimWorld w(c, 1);
  drive(w, 0.4, 0.4, 2.0);
  const Pose2D r = w.robotTruth().pose;
  ASSERT_GT(r.x, 1.3);  // it drove, pushing
  const GameElement e = w.elements()[0];
  EXPECT_NEAR(e.pose.x, r.x + 0.10 + 0.035, 1e-6);  // against the front face
  EXPECT_NEAR(e.pose.y, 1.05 + 0.08, 1e-6);         // not slid off sideways as off a circle
}
