// The opponent behaves like a robot with its own sensors, in every mode: it never touches our
// parked robot (it keeps its safety distance), and blocked by us it leaves within its configured
// time. The player plays the game: alone on the 2009 and 2008 tables it scores within 90 s.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "robot_sim/world/sim_world.h"
#include "world_test_support.h"

using namespace robot_sim;

namespace {
// The robot's own world, table and description (config/<robot>.sim.yaml's sim/world,
// config/<robot>.yaml's table and robot).
WorldConfig robotWorld(const std::string& robot) {
  const std::string dir = ROBOT_CONFIG_DIR;
  return parseWorldConfig(robot_core::Params::fromYamlFile(dir + "/" + robot + ".sim.yaml", "sim/world"),
                          robot_core::Params::fromYamlFile(dir + "/" + robot + ".yaml", "table"),
                          robot_core::Params::fromYamlFile(dir + "/" + robot + ".yaml", "robot"));
}

struct Watch {
  double min_clearance = 1e9;  // between the opponent's circle and our outline [m]
  double longest_near = 0.0;   // [s] longest stretch within the safety distance (+2 cm)
  double near_total = 0.0;     // [s]
  double travelled = 0.0;      // [m] by the opponent
};

// Runs a match of `seconds` with our robot parked where the config puts it, watching the opponent.
Watch watch(WorldConfig c, double seconds, unsigned seed = 1) {
  c.match.start_switch = "";  // the match starts at once
  SimWorld w(c, seed);
  Watch out;
  double near_for = 0.0;
  Pose2D last = w.opponentTruth().pose;
  const double r = c.opponent.radius;
  for (long i = 0, n = std::lround(seconds / c.dt); i < n; ++i) {
    w.step();
    const BodyTruth them = w.opponentTruth();
    const double clearance = w.footprint().circleContact(w.robotTruth().pose, Circle{them.pose.x, them.pose.y, r}).clearance;
    out.min_clearance = std::min(out.min_clearance, clearance);
    near_for = clearance < c.opponent.safety_distance + 0.02 ? near_for + c.dt : 0.0;
    if (near_for > 0.0) out.near_total += c.dt;
    out.longest_near = std::max(out.longest_near, near_for);
    out.travelled += std::hypot(them.pose.x - last.x, them.pose.y - last.y);
    last = them.pose;
  }
  return out;
}

// How long a blocked opponent may stay: its wait, its back-off, a pause at a waypoint it reached beside us.
double leaveWithin(const OpponentConfig& o) { return o.give_way_after + o.back_off / o.speed + o.pause + 0.5; }

void expectNeverTouchedAndLeaves(const WorldConfig& c, const char* mode, bool must_meet) {
  const Watch seen = watch(c, 90.0);
  EXPECT_GT(seen.travelled, 3.0) << mode << ": the opponent hardly moved";
  EXPECT_GE(seen.min_clearance, c.opponent.safety_distance - 1e-6) << mode << ": came within its safety distance";
  if (must_meet) {
    EXPECT_GT(seen.near_total, 0.5) << mode << ": never met our robot: the case is not tested";
  }
  EXPECT_LE(seen.longest_near, leaveWithin(c.opponent)) << mode << ": stayed blocked";
}
}  // namespace

TEST(Opponent, RandomWalkNeverTouchesAParkedRobotAndLeaves) {
  WorldConfig c = robotWorld("eurobot2009");
  c.robot.start = Pose2D{1.5, 1.05, 0.0};  // parked in the middle of where it walks
  c.opponent.mode = "random_walk";
  c.opponent.margin = 0.8;  // its targets near the middle: it meets our robot
  expectNeverTouchedAndLeaves(c, "random_walk", true);
}

TEST(Opponent, RouteNeverTouchesAParkedRobotAndLeaves) {
  WorldConfig c = robotWorld("eurobot2009");
  c.robot.start = Pose2D{1.5, 0.35, 0.0};  // parked on its route
  c.opponent.mode = "script";
  c.opponent.waypoints = {{2.7, 0.35}, {0.3, 0.35}, {0.3, 1.75}, {2.7, 1.75}};
  expectNeverTouchedAndLeaves(c, "route", true);
}

TEST(Opponent, BlockerNeverTouchesAParkedRobotAndLeaves) {
  WorldConfig c = robotWorld("eurobot2009");
  c.robot.start = Pose2D{1.5, 0.35, -M_PI / 2};  // on the spot it goes to block
  c.opponent.mode = "script";
  c.opponent.waypoints = {{1.5, 0.3}};
  c.opponent.pause = 1e6;
  expectNeverTouchedAndLeaves(c, "blocker", true);
}

TEST(Opponent, PlayerNeverTouchesAParkedRobotAndLeaves) {
  WorldConfig c = robotWorld("eurobot2009");
  c.robot.start = Pose2D{2.0, 0.68, 0.0};  // parked among its columns, on its way to the temple
  c.opponent.mode = "player";
  const Watch seen = watch(c, 90.0);
  EXPECT_GE(seen.min_clearance, c.opponent.safety_distance - 1e-6);
  EXPECT_LE(seen.longest_near, leaveWithin(c.opponent));
}

TEST(Opponent, StaticAndHeldOpponentsStay) {
  WorldConfig c = robotWorld("eurobot2009");
  c.opponent.mode = "static";
  const Watch seen = watch(c, 10.0);
  EXPECT_EQ(seen.travelled, 0.0);
}

TEST(Opponent, NothingMovesBeforeTheStart) {
  WorldConfig c = robotWorld("eurobot2009");
  c.opponent.mode = "player";
  SimWorld w(c, 1);  // the start cord still in
  run(w, 5.0);
  EXPECT_EQ(w.opponentTruth().pose.x, c.opponent.start.x);
  EXPECT_EQ(w.opponentTruth().pose.y, c.opponent.start.y);
}

namespace {
// The player alone on the robot's table (our robot parked in its start zone) for a match.
MatchProgress playAlone(const std::string& robot, unsigned seed) {
  WorldConfig c = robotWorld(robot);
  c.opponent.mode = "player";
  SimWorld w(c, seed);
  EXPECT_TRUE(w.startMatch());
  run(w, c.match.duration + 0.5);
  return w.match();
}
}  // namespace

TEST(Opponent, APlayerAloneOnThe2009TableScores) {
  const MatchProgress m = playAlone("eurobot2009", 1);
  EXPECT_TRUE(m.over);
  EXPECT_EQ(m.score_ours, 0);
  EXPECT_GE(m.score_opponent, 3) << "colours: ours " << m.colour_ours << ", theirs " << m.colour_opponent;
}

TEST(Opponent, APlayerAloneOnThe2008TableScores) {
  const MatchProgress m = playAlone("logion", 1);
  EXPECT_TRUE(m.over);
  EXPECT_EQ(m.score_ours, 0);
  EXPECT_GE(m.score_opponent, 3) << "colours: ours " << m.colour_ours << ", theirs " << m.colour_opponent;
}
