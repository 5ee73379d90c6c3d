// The simulated referee: points go to the team the zone's rules say. A shared zone ("placer")
// credits the robot that last moved the element; a colour zone that colour's team, our colour
// being the start zone our robot stands in at the start.
#include <gtest/gtest.h>

#include <cmath>

#include "robot_sim/world/config.h"
#include "robot_sim/world/sim_world.h"
#include "world_test_support.h"

using namespace robot_sim;

namespace {
WorldConfig baseConfig() {
  WorldConfig c;
  c.robot.start = Pose2D{0.25, 1.8, 0.0};
  c.robot.radius = 0.15;
  addGripDriveMotors(c);
  SwitchConfig cord;
  cord.type = "manual";
  cord.initially_closed = true;
  c.robot.switches["start_cord"] = cord;
  c.match.start_switch = "start_cord";
  c.match.duration = 90.0;
  Zone red, green, temple;
  red.name = "red";
  red.x0 = 0.0, red.y0 = 1.6, red.x1 = 0.5, red.y1 = 2.1;
  green.name = "green";
  green.x0 = 2.5, green.y0 = 1.6, green.x1 = 3.0, green.y1 = 2.1;
  c.table.start_zones = {red, green};
  temple.name = "temple";
  temple.x0 = 1.2, temple.y0 = 0.0, temple.x1 = 1.8, temple.y1 = 0.6;
  temple.points = 3;
  temple.team = "placer";
  Zone green_build;
  green_build.name = "green_build";
  green_build.x0 = 2.6, green_build.y0 = 0.0, green_build.x1 = 3.0, green_build.y1 = 0.4;
  green_build.points = 2;
  green_build.team = "green";
  c.table.score_zones = {temple, green_build};
  c.opponent.enabled = true;
  c.opponent.mode = "static";
  c.opponent.start = Pose2D{2.75, 1.8, M_PI};
  c.opponent.speed = 0.3;
  c.opponent.pause = 0.0;
  return c;
}

GameElement column(double x, double y) {
  GameElement e;
  e.kind = "column";
  e.pose = Pose2D{x, y, 0.0};
  e.radius = 0.035;
  e.height = 0.03;
  return e;
}
}  // namespace

TEST(Referee, OurColourIsTheStartZoneWeStandInAtTheStart) {
  SimWorld w(baseConfig(), 1);
  EXPECT_EQ(w.match().colour_ours, "");  // not before the start
  ASSERT_TRUE(w.startMatch());
  EXPECT_FALSE(w.startMatch()) << "a second start does nothing";
  run(w, 0.01);
  EXPECT_TRUE(w.match().started);
  EXPECT_EQ(w.match().colour_ours, "red");
  EXPECT_EQ(w.match().colour_opponent, "green");
}

TEST(Referee, TheOpponentsPushIntoASharedZoneIsTheirs) {
  WorldConfig c = baseConfig();
  // The opponent drives down x = 1.5 from y = 1.2 to y = 0.2 and pushes the column ahead of
  // it into the temple; our robot stays at home.
  c.opponent.mode = "script";
  c.opponent.start = Pose2D{1.5, 1.3, -M_PI / 2};
  c.opponent.waypoints = {{1.5, 0.2}};
  c.table.elements = {column(1.5, 1.0)};
  SimWorld w(c, 1);
  w.startMatch();
  run(w, 8.0);
  const MatchProgress m = w.match();
  ASSERT_TRUE(c.table.score_zones[0].contains(w.elements()[0].pose.x, w.elements()[0].pose.y))
      << "the opponent should have pushed the column into the temple: at " << w.elements()[0].pose.x << ", "
      << w.elements()[0].pose.y;
  EXPECT_EQ(w.elements()[0].moved_by, Mover::opponent);
  EXPECT_EQ(m.score_ours, 0);
  EXPECT_EQ(m.score_opponent, 3);
  const auto events = w.scoreEvents();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].element, "column#0");
  EXPECT_EQ(events[0].zone, "temple");
  EXPECT_EQ(events[0].points, 3);
  EXPECT_EQ(events[0].team, Mover::opponent);
  EXPECT_GT(events[0].time, 0.0);
  EXPECT_LT(events[0].time, 8.0);
}

TEST(Referee, AColumnWePushIntoASharedZoneIsOurs) {
  WorldConfig c = baseConfig();
  c.opponent.enabled = false;
  c.robot.start = Pose2D{1.5, 1.2, -M_PI / 2};
  c.table.elements = {column(1.5, 0.95)};
  SimWorld w(c, 1);
  w.startMatch();
  w.setMotorCommand("left", 0.2);
  w.setMotorCommand("right", 0.2);
  while (w.robotTruth().pose.y > 0.55) w.step();
  w.setMotorCommand("left", 0.0);
  w.setMotorCommand("right", 0.0);
  run(w, 0.5);
  EXPECT_EQ(w.elements()[0].moved_by, Mover::ours);
  EXPECT_EQ(w.match().score_ours, 3);
  EXPECT_EQ(w.match().score_opponent, 0);
}

TEST(Referee, AColourZoneScoresForThatColourWhoeverPutTheElementThere) {
  WorldConfig c = baseConfig();
  c.opponent.enabled = false;
  c.table.elements = {column(2.8, 0.2)};  // lies in green's zone from the start
  SimWorld w(c, 1);
  w.startMatch();
  run(w, 0.1);
  EXPECT_EQ(w.match().score_ours, 0);
  EXPECT_EQ(w.match().score_opponent, 2) << "green is the opponent's colour";
}

TEST(Referee, NothingCountsBeforeTheStartAndTheScoreFreezesAtTheEnd) {
  WorldConfig c = baseConfig();
  c.opponent.enabled = false;
  c.match.duration = 1.0;
  c.robot.start = Pose2D{1.5, 1.2, -M_PI / 2};
  c.table.elements = {column(1.5, 0.95)};
  SimWorld w(c, 1);
  w.setMotorCommand("left", 0.2);
  w.setMotorCommand("right", 0.2);
  while (w.robotTruth().pose.y > 0.55) w.step();  // pushed in before the start
  run(w, 0.2);
  EXPECT_EQ(w.match().score_ours, 0);
  EXPECT_TRUE(w.scoreEvents().empty());
  w.startMatch();
  run(w, 0.1);
  EXPECT_EQ(w.match().score_ours, 3) << "it lies there at the start, last moved by us";
  // Back out, then drive in again after the match end: the score stays frozen.
  w.setMotorCommand("left", -0.5);
  w.setMotorCommand("right", -0.5);
  run(w, 1.5);
  EXPECT_TRUE(w.match().over);
  const int frozen = w.match().score_ours;
  const std::size_t events = w.scoreEvents().size();
  w.setMotorCommand("left", 0.5);
  w.setMotorCommand("right", 0.5);
  run(w, 2.0);
  EXPECT_EQ(w.match().score_ours, frozen);
  EXPECT_EQ(w.scoreEvents().size(), events);
}
