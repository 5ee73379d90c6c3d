// Avoidance geometry: what blocks the route, what is the border, where a detour goes.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hal_nodes/driver/avoidance.h"

using namespace hal_nodes::driver;

namespace {
AvoidanceConfig config() {
  AvoidanceConfig c;
  c.robot_radius = 0.18;
  c.opponent_radius = 0.2;
  c.margin = 0.05;
  c.detection_distance = 0.7;
  c.braking_distance = 0.15;
  return c;  // clearance 0.43
}
const std::vector<Point2D> kRoute = {{0.5, 1.0}, {2.5, 1.0}};
}  // namespace

TEST(Avoidance, ConfigIsChecked) {
  EXPECT_TRUE(config().invalidReason().empty());
  AvoidanceConfig c = config();
  c.detection_distance = 0.3;  // shorter than braking + clearance
  EXPECT_FALSE(c.invalidReason().empty());
  AvoidanceConfig::Mode m;
  EXPECT_TRUE(AvoidanceConfig::parseMode("detour", &m));
  EXPECT_EQ(m, AvoidanceConfig::Mode::DETOUR);
  EXPECT_FALSE(AvoidanceConfig::parseMode("swerve", &m));
}

TEST(Avoidance, OpponentOnTheRouteAheadBlocks) {
  const Avoidance a(config());
  const auto hit = a.check(kRoute, {{1.1, 1.2}});
  ASSERT_TRUE(hit.blocked);
  // Touching starts clearance-wide before the closest approach at 0.6 m.
  EXPECT_NEAR(hit.along, 0.6 - std::sqrt(0.43 * 0.43 - 0.2 * 0.2), 1e-9);
  EXPECT_NEAR(hit.direction.x, 1.0, 1e-12);
}

TEST(Avoidance, OffTheRouteOrTooFarAheadDoesNotBlock) {
  const Avoidance a(config());
  EXPECT_FALSE(a.check(kRoute, {{1.1, 1.5}}).blocked);   // 0.5 m beside: clearance 0.43
  EXPECT_FALSE(a.check(kRoute, {{1.7, 1.0}}).blocked);   // touching from 0.77 m on: beyond detection
  EXPECT_TRUE(a.check(kRoute, {{1.6, 1.0}}).blocked);    // touching from 0.67 m on: within 0.7 m
  EXPECT_FALSE(a.check(kRoute, {}).blocked);
  EXPECT_FALSE(a.check({{0.5, 1.0}}, {{0.6, 1.0}}).blocked);  // no route left
  EXPECT_FALSE(a.check(kRoute, {{0.3, 1.1}}).blocked);   // behind the robot
  EXPECT_FALSE(a.check(kRoute, {{0.5, 1.3}}).blocked);   // level with it, beside
  EXPECT_TRUE(a.check(kRoute, {{0.75, 1.2}}).blocked);   // near and ahead: the opponent's centre is within clearance
  // Near and well to the side (after a stop beside it): its centre, an opponent radius beyond the
  // echo, stays out of the clearance along the route, so the robot may leave.
  EXPECT_FALSE(a.check(kRoute, {{0.6, 1.3}}).blocked);
}

TEST(Avoidance, NearestOfSeveralAndAlongABend) {
  const Avoidance a(config());
  const std::vector<Point2D> bent = {{0.5, 1.0}, {0.8, 1.0}, {0.8, 1.6}};
  const auto hit = a.check(bent, {{1.5, 1.3}, {0.8, 1.4}, {0.9, 1.05}});
  ASSERT_TRUE(hit.blocked);
  EXPECT_NEAR(hit.obstacle.x, 0.9, 1e-12);  // the nearest along the route
}

TEST(Avoidance, BorderEchoesAreNotTheOpponent) {
  const Avoidance a(config());
  EXPECT_FALSE(a.plausibleObstacle({2.98, 1.0}));
  EXPECT_FALSE(a.plausibleObstacle({1.0, 0.02}));
  EXPECT_FALSE(a.plausibleObstacle({-0.3, 1.0}));
  EXPECT_TRUE(a.plausibleObstacle({1.5, 1.0}));
}

TEST(Avoidance, DetourGoesAroundOnTheSideWithRoom) {
  const Avoidance a(config());
  const std::vector<Point2D> obs = {{1.1, 1.0}};
  const auto hit = a.check(kRoute, obs);
  std::vector<Point2D> wps;
  ASSERT_TRUE(a.detour(hit, obs, &wps));
  ASSERT_EQ(wps.size(), 2u);
  for (const auto& w : wps) {
    EXPECT_GE(std::hypot(w.x - 1.1, w.y - 1.0), config().clearance());
    EXPECT_GT(w.y, 0.23);
    EXPECT_LT(w.y, 2.1 - 0.23);
  }
  // The legs robot -> w1 -> w2 -> goal stay clear of the opponent.
  const std::vector<Point2D> route = {{0.5, 1.0}, wps[0], wps[1], {2.5, 1.0}};
  EXPECT_FALSE(a.check(route, obs).blocked);
}

TEST(Avoidance, DetourNearTheEdgeTakesTheOtherSideOrNone) {
  const Avoidance a(config());
  // Route along y = 0.5: below it there is no room for the robot, so the detour goes above.
  const std::vector<Point2D> low = {{0.5, 0.5}, {2.5, 0.5}};
  const std::vector<Point2D> obs = {{1.1, 0.5}};
  std::vector<Point2D> wps;
  ASSERT_TRUE(a.detour(a.check(low, obs), obs, &wps));
  EXPECT_GT(wps[0].y, 0.5);
  // Opponents on both sides of the way: no detour, the driver stops.
  const std::vector<Point2D> wall = {{1.1, 1.0}, {1.1, 1.5}, {1.1, 0.5}};
  EXPECT_FALSE(a.detour(a.check(kRoute, wall), wall, &wps));
}

// A wide ultrasonic cone (SRF02, 0.96 rad) sees a border off its axis; placed on the axis the
// echo would land inside the table, on the route. The border range over the cone explains it.
TEST(Avoidance, BorderSeenOffAxisIsExplained) {
  AvoidanceConfig c = config();
  c.table_length = 3.0;
  c.table_width = 2.1;
  c.border_echo_tolerance = 0.1;
  const Avoidance a(c);
  // Sensor at (1.5, 1.7) looking 45 deg left of +x: the axis reaches the y = 2.1 border at
  // 0.4 * sqrt(2) = 0.566 m, but the cone's edge (45 + 27.5 deg) reaches it at 0.4 / sin(72.5) = 0.419 m.
  const Pose2D sensor{1.5, 1.7, M_PI / 4};
  EXPECT_NEAR(a.borderRange(sensor, 0.96), 0.4 / std::sin(M_PI / 4 + 0.48), 1e-9);
  EXPECT_TRUE(a.borderExplains(sensor, 0.96, 0.42));
  EXPECT_TRUE(a.borderExplains(sensor, 0.96, 0.35));  // within the tolerance (filter lag, localization error)
  // That echo placed on the axis is inside the table, 0.30 m from the border: not dropped by border_margin.
  EXPECT_TRUE(a.plausibleObstacle({1.5 + 0.42 * std::cos(M_PI / 4), 1.7 + 0.42 * std::sin(M_PI / 4)}));
  // The opponent, clearly nearer than any border in the cone: kept.
  EXPECT_FALSE(a.borderExplains(sensor, 0.96, 0.25));
  // A narrow beam straight at the border reads the perpendicular distance.
  EXPECT_NEAR(a.borderRange({1.5, 1.7, M_PI / 2}, 0.08), 0.4, 1e-9);
  // A wall normal inside the cone is its closest point.
  EXPECT_NEAR(a.borderRange({2.8, 1.0, 0.3}, 0.96), 0.2, 1e-9);
}

TEST(Avoidance, OpponentInTheMiddleOfTheTableIsNotTheBorder) {
  const Avoidance a(config());
  // Looking along +x from the middle: the border is 1.3 m away, an echo at 0.5 m is something else.
  EXPECT_NEAR(a.borderRange({1.7, 1.05, 0.0}, 0.96), 1.3, 1e-9);
  EXPECT_FALSE(a.borderExplains({1.7, 1.05, 0.0}, 0.96, 0.5));
  EXPECT_TRUE(a.borderExplains({1.7, 1.05, 0.0}, 0.96, std::numeric_limits<double>::infinity()));
}
