// follow_path's controller on the kinematic model: a curve through 6 checkpoints followed within
// 30 mm, every checkpoint counted as passed, limits kept.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hal_nodes/driver/hermite_path.h"
#include "hal_nodes/driver/path_follower.h"
#include "test_driver_support.h"

using namespace hal_nodes::driver;
using namespace hal_nodes::driver::test;

namespace {
constexpr double kDt = 0.02;

double distanceToCurve(const std::vector<PathSample>& curve, double x, double y) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < curve.size(); ++i) {
    const double ax = curve[i - 1].x, ay = curve[i - 1].y, bx = curve[i].x, by = curve[i].y;
    const double l2 = (bx - ax) * (bx - ax) + (by - ay) * (by - ay);
    const double t = l2 > 0 ? std::clamp(((x - ax) * (bx - ax) + (y - ay) * (by - ay)) / l2, 0.0, 1.0) : 0.0;
    best = std::min(best, std::hypot(ax + t * (bx - ax) - x, ay + t * (by - ay) - y));
  }
  return best;
}

struct PathRun {
  double max_deviation = 0.0, final_error = 0.0;
  int passed = 0, violations = 0;
  bool finished = false;
};

PathRun follow(const Pose2D& start, const std::vector<Checkpoint>& cps, double max_speed) {
  const AutopilotConfig cfg = robotConfig();
  PathFollower f(cfg, PathFollowerConfig());
  const HermitePath path(start, cps);
  const auto curve = path.sample(0.002);  // the reference, finer than the follower's own
  f.start(path.sample(PathFollowerConfig().sample_step), 0.01, max_speed);
  KinematicModel robot(start, 1, 0.02);
  PathRun run;
  const LoopResult r = closedLoop(
      robot, cfg.limits, kDt, 60.0, [&](const Pose2D& p, const Twist2D& l) { return f.step(p, l); }, [&]() { return f.done(); },
      [&](const KinematicModel& m) {
        run.max_deviation = std::max(run.max_deviation, distanceToCurve(curve, m.pose().x, m.pose().y));
        run.passed = std::max(run.passed, f.segment());
      });
  run.finished = r.finished;
  run.violations = r.limit_violations;
  run.passed = std::max(run.passed, f.segment());
  run.final_error = std::hypot(robot.pose().x - cps.back().x, robot.pose().y - cps.back().y);
  return run;
}
}  // namespace

TEST(PathFollower, SixCheckpointsWithin30mmOfTheCurve) {
  const std::vector<Checkpoint> cps = {{0.8, 0.5}, {1.3, 0.9}, {1.8, 0.6}, {2.3, 1.2}, {1.8, 1.6, true, M_PI}, {1.0, 1.3}};
  for (double speed : {0.25, 0.0 /* the robot's limit */}) {
    const PathRun run = follow({0.4, 0.4, 0.3}, cps, speed);
    SCOPED_TRACE(::testing::Message() << "max_speed " << speed);
    EXPECT_TRUE(run.finished);
    EXPECT_LE(run.max_deviation, 0.030);
    EXPECT_LE(run.final_error, 0.010);
    EXPECT_EQ(run.passed, 6);
    EXPECT_EQ(run.violations, 0);
  }
}

TEST(PathFollower, CheckpointBesideTheRobotTurnsInPlaceFirst) {
  const PathRun run = follow({1.0, 1.0, 0.0}, {{1.0, 1.5}, {1.5, 1.5}}, 0.0);
  EXPECT_TRUE(run.finished);
  EXPECT_LE(run.final_error, 0.010);
  EXPECT_EQ(run.passed, 2);
}

TEST(PathFollower, RestartFromTheCurrentPoseAfterAnEdit) {
  // What the device does on a path edit: a new curve from where the robot is, on its heading.
  const AutopilotConfig cfg = robotConfig();
  PathFollower f(cfg, PathFollowerConfig());
  KinematicModel robot({0.5, 0.5, 0.0});
  VelocityLimiter lim(cfg.limits);
  std::vector<Checkpoint> queue = {{1.5, 0.5}, {2.0, 1.0}};
  f.start(HermitePath(robot.pose(), queue).sample(0.005), 0.01, 0.0);
  for (int i = 0; i < 60; ++i) robot.step(lim.apply(f.step(robot.pose(), lim.last()), kDt), kDt);
  ASSERT_GT(robot.velocity().v, 0.2);
  queue[1] = {2.0, 0.2};  // replace the last checkpoint while driving
  f.start(HermitePath(robot.pose(), queue).sample(0.005), 0.01, 0.0);
  double t = 0.0;
  while (!f.done() && t < 20.0) {
    robot.step(lim.apply(f.step(robot.pose(), lim.last()), kDt), kDt);
    t += kDt;
  }
  ASSERT_TRUE(f.done());
  EXPECT_LE(std::hypot(robot.pose().x - 2.0, robot.pose().y - 0.2), 0.015);
}
