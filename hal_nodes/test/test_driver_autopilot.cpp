// The Autopilot and the relative moves on a kinematic model with a one-period command delay and
// a motor lag: goals reached within 10 mm / 2 degrees, no overshoot beyond 20 mm, limits kept.
#include <gtest/gtest.h>

#include <cmath>

#include "hal_nodes/driver/relative_moves.h"
#include "test_driver_support.h"

using namespace hal_nodes::driver;
using namespace hal_nodes::driver::test;

namespace {
constexpr double kDt = 0.02;  // 50 Hz, the configured driver rate
constexpr double kDeg = M_PI / 180.0;

struct Case {
  Pose2D start, goal;
};

struct Outcome {
  double position_error, heading_error, overshoot, time;
  int violations;
  bool finished;
};

Outcome runGoto(const Case& c, double pos_tol = 0.01, double ang_tol = 2 * kDeg, bool reverse = false) {
  const AutopilotConfig cfg = robotConfig();
  Autopilot ap(cfg);
  AutopilotGoal g;
  g.target = c.goal;
  g.position_tolerance = pos_tol;
  g.angle_tolerance = ang_tol;
  g.allow_reverse = reverse;
  ap.start(g, c.start);
  KinematicModel robot(c.start, 1, 0.02);
  const double ux = c.goal.x - c.start.x, uy = c.goal.y - c.start.y, n = std::hypot(ux, uy);
  double overshoot = 0.0;
  const LoopResult r = closedLoop(
      robot, cfg.limits, kDt, 30.0, [&](const Pose2D& p, const Twist2D& last) { return ap.step(p, last, &robot.velocity()); },
      [&]() { return ap.done(); },
      [&](const KinematicModel& m) {
        if (n > 1e-6)
          overshoot = std::max(overshoot, ((m.pose().x - c.goal.x) * ux + (m.pose().y - c.goal.y) * uy) / n);
      });
  const Pose2D p = robot.pose();
  return {std::hypot(p.x - c.goal.x, p.y - c.goal.y), std::fabs(wrapAngle(p.theta - c.goal.theta)), overshoot, r.time,
          r.limit_violations, r.finished};
}
}  // namespace

TEST(Autopilot, ReachesGoalsAcrossTheTableWithoutOvershoot) {
  const Case cases[] = {
      {{0.25, 0.25, 0.0}, {2.7, 1.8, 0.0}},          // across the table
      {{2.7, 1.8, M_PI}, {0.3, 0.3, -M_PI / 2}},     // and back, final turn
      {{1.5, 1.0, 0.0}, {1.5, 1.6, 0.0}},            // goal to the side
      {{1.5, 1.0, 0.0}, {0.9, 1.0, 0.0}},            // goal behind
      {{1.0, 1.0, 0.3}, {1.05, 1.02, 0.3}},          // short hop
      {{1.0, 1.0, 0.0}, {1.0, 1.0, 2.5}},            // turn only
      {{0.4, 1.7, -0.5}, {2.6, 0.4, 1.0}},           // long diagonal
      {{2.0, 0.5, 1.2}, {2.0, 0.52, 1.2}},           // 2 cm sideways: the near-goal case
  };
  for (const auto& c : cases) {
    const Outcome o = runGoto(c);
    SCOPED_TRACE(::testing::Message() << "goal (" << c.goal.x << ", " << c.goal.y << ", " << c.goal.theta << ")");
    EXPECT_TRUE(o.finished);
    EXPECT_LE(o.position_error, 0.010);
    EXPECT_LE(o.heading_error, 2 * kDeg);
    EXPECT_LE(o.overshoot, 0.020);
    EXPECT_EQ(o.violations, 0);
  }
}

TEST(Autopilot, SlowsDownAsItArrives) {
  const AutopilotConfig cfg = robotConfig();
  Autopilot ap(cfg);
  AutopilotGoal g;
  g.target = {2.0, 0.0, 0.0};
  ap.start(g, {0.0, 0.0, 0.0});
  // Facing the goal: the desired speed falls with the distance left, to zero at the goal.
  double prev = 1e9;
  for (double x = 1.0; x <= 1.995; x += 0.05) {
    const double v = ap.step({x, 0.0, 0.0}, {0.3, 0.0}).v;
    EXPECT_LE(v, prev + 1e-12) << "at x = " << x;
    EXPECT_GT(v, 0.0);
    prev = v;
  }
  // 5 cm from the goal: no more than the speed curve's share of the top speed, under a third of it.
  EXPECT_LE(prev, cfg.limits.max_linear_speed * cfg.speed_curve.fraction(0.05) + 1e-9);
  EXPECT_LT(prev, cfg.limits.max_linear_speed / 3.0);
}

TEST(Autopilot, ReversesWhenAllowedAndTheGoalIsBehind) {
  const Outcome o = runGoto({{1.5, 1.0, 0.0}, {1.0, 1.0, 0.0}}, 0.01, 2 * kDeg, true);
  EXPECT_TRUE(o.finished);
  EXPECT_LE(o.position_error, 0.010);
  // Driving backwards, it never turns around: far faster than the forward version's two half-turns.
  EXPECT_LT(o.time, runGoto({{1.5, 1.0, 0.0}, {1.0, 1.0, 0.0}}).time - 0.5);
}

TEST(Autopilot, SpeedLimitOfTheGoalIsKept) {
  const AutopilotConfig cfg = robotConfig();
  Autopilot ap(cfg);
  AutopilotGoal g;
  g.target = {2.0, 0.0, 0.0};
  g.max_speed = 0.2;
  ap.start(g, {0.0, 0.0, 0.0});
  KinematicModel robot({0.0, 0.0, 0.0});
  double vmax = 0.0;
  closedLoop(robot, cfg.limits, kDt, 30.0, [&](const Pose2D& p, const Twist2D& l) { return ap.step(p, l); },
             [&]() { return ap.done(); }, [&](const KinematicModel& m) { vmax = std::max(vmax, m.velocity().v); });
  EXPECT_LE(vmax, 0.2 + 1e-9);
  EXPECT_GT(vmax, 0.19);
}

TEST(Autopilot, WaypointIsPassedWithoutStopping) {
  const AutopilotConfig cfg = robotConfig();
  Autopilot ap(cfg);
  AutopilotGoal g;
  g.target = {1.0, 0.0, 0.0};
  g.position_tolerance = 0.05;
  g.final_heading = false;
  ap.start(g, {0.0, 0.0, 0.0});
  KinematicModel robot({0.0, 0.0, 0.0});
  VelocityLimiter lim(cfg.limits);
  double t = 0.0;
  while (!ap.done() && t < 10.0) {
    const Twist2D d = ap.step(robot.pose(), lim.last());
    robot.step(lim.apply(d, kDt), kDt);
    t += kDt;
  }
  ASSERT_TRUE(ap.done());
  EXPECT_GT(robot.velocity().v, 0.05);  // still rolling into the next leg
}

TEST(Autopilot, ProgressAndRemainingDistance) {
  Autopilot ap(robotConfig());
  AutopilotGoal g;
  g.target = {1.0, 0.0, 0.0};
  ap.start(g, {0.0, 0.0, 0.0});
  ap.step({0.25, 0.0, 0.0}, {});
  EXPECT_NEAR(ap.remainingDistance(), 0.75, 1e-12);
  EXPECT_NEAR(ap.progressPercent(), 25.0, 1e-9);
}

TEST(Autopilot, CancelMeansZeroNextPeriod) {
  // The device's stop path: reset the limiter (no ramp) and send what it holds.
  const AutopilotConfig cfg = robotConfig();
  VelocityLimiter lim(cfg.limits);
  for (int i = 0; i < 50; ++i) lim.apply({0.5, 1.0}, kDt);
  ASSERT_GT(lim.last().v, 0.1);
  lim.reset();
  const Twist2D next = lim.last();
  EXPECT_EQ(next.v, 0.0);
  EXPECT_EQ(next.w, 0.0);
}

TEST(StraightMove, ForwardAndBackwardHoldTheHeading) {
  const AutopilotConfig cfg = robotConfig();
  for (double d : {0.3, -0.2, 0.004}) {
    StraightMove m(cfg);
    const Pose2D start{1.0, 1.0, 0.7};
    m.start(start, d, 0.003, 0.0);
    KinematicModel robot(start);
    const LoopResult r = closedLoop(robot, cfg.limits, kDt, 20.0, [&](const Pose2D& p, const Twist2D& l) { return m.step(p, l); },
                                    [&]() { return m.done(); });
    EXPECT_TRUE(r.finished);
    EXPECT_EQ(r.limit_violations, 0);
    const Pose2D p = robot.pose();
    const double along = (p.x - start.x) * std::cos(start.theta) + (p.y - start.y) * std::sin(start.theta);
    EXPECT_NEAR(along, d, 0.003) << "distance " << d;
    EXPECT_NEAR(wrapAngle(p.theta - start.theta), 0.0, 0.5 * kDeg);
  }
}

TEST(Rotation, TurnsByAnyAngleIncludingMoreThanHalfATurn) {
  const AutopilotConfig cfg = robotConfig();
  for (double a : {M_PI / 2, -2.5, 2 * M_PI, 0.01}) {
    Rotation rot(cfg);
    const Pose2D start{1.0, 1.0, 3.0};
    rot.start(start, a, 1 * kDeg, 0.0);
    KinematicModel robot(start);
    double turned = 0.0, last = start.theta;
    const LoopResult r = closedLoop(robot, cfg.limits, kDt, 20.0, [&](const Pose2D& p, const Twist2D& l) { return rot.step(p, l); },
                                    [&]() { return rot.done(); },
                                    [&](const KinematicModel& m) {
                                      turned += wrapAngle(m.pose().theta - last);
                                      last = m.pose().theta;
                                    });
    EXPECT_TRUE(r.finished);
    EXPECT_EQ(r.limit_violations, 0);
    turned += wrapAngle(robot.pose().theta - last);
    EXPECT_NEAR(turned, a, 1 * kDeg) << "angle " << a;
    EXPECT_NEAR(std::hypot(robot.pose().x - 1.0, robot.pose().y - 1.0), 0.0, 1e-9);
  }
}
