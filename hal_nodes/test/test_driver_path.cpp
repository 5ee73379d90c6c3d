// follow_path's controller on the kinematic model: a curve through 6 checkpoints followed within
// 30 mm, every checkpoint counted as passed, limits kept; a sharp bend over a range of motor lags.
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

// The actuation lag of the model: commands `delay` periods late, then a first-order motor.
struct Lag {
  int delay = 1;
  double time_constant = 0.02;
};

PathRun follow(const Pose2D& start, const std::vector<Checkpoint>& cps, double max_speed,
               const AutopilotConfig& cfg = robotConfig(), const PathFollowerConfig& pcfg = PathFollowerConfig(),
               const Lag& lag = Lag()) {
  PathFollower f(cfg, pcfg);
  const HermitePath path(start, cps);
  const auto curve = path.sample(0.002);  // the reference, finer than the follower's own
  f.start(path.sample(pcfg.sample_step), 0.01, max_speed);
  KinematicModel robot(start, lag.delay, lag.time_constant);
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

TEST(PathFollower, ALoopBackToTheStartIsDrivenWhole) {
  // The robot stands on the last checkpoint: the curve leaves and comes back; it is not done at once.
  const std::vector<Checkpoint> cps = {{0.8, 1.2}, {1.5, 1.25}, {1.2, 0.6}};
  const PathRun run = follow({1.2, 0.6, 0.0}, cps, 0.0);
  EXPECT_TRUE(run.finished);
  EXPECT_EQ(run.passed, 3);
  EXPECT_LE(run.final_error, 0.010);
  EXPECT_LE(run.max_deviation, 0.030);
}

// Logion's path settings (config/logion.yaml, hal/driver/path).
PathFollowerConfig logionPathConfig() {
  PathFollowerConfig pcfg;
  pcfg.max_lateral_accel = 0.18;
  pcfg.lookahead_time = 0.16;
  return pcfg;
}

// Logion's driver configuration (config/logion.yaml) and the path of driver_sim_logion, whose
// checkpoint (2.5, 1.5) the curve leaves almost backwards: a bend of ~2 cm radius taken at ~3 cm/s.
// Over a range of actuation lags around Logion's (HBmotor loop over I2C, motor time constant
// ~0.08 s) the robot stays within 22 mm of the curve. With heading feedback proportional to the
// speed only (heading_correction_speed 0) the heading lags the tangent at that checkpoint and the
// way out runs off the curve for many of these lags.
TEST(PathFollower, SharpBendFollowedWhateverTheActuationLag) {
  const AutopilotConfig cfg = logionConfig();
  const PathFollowerConfig pcfg = logionPathConfig();
  const std::vector<Checkpoint> cps = {{0.9, 1.55}, {1.3, 1.75}, {1.7, 1.45}, {2.1, 1.7}, {2.5, 1.5}, {2.1, 1.3}};
  for (int delay = 1; delay <= 4; ++delay) {
    for (double time_constant : {0.02, 0.05, 0.08, 0.12}) {
      const PathRun run = follow({0.5, 1.5, 0.0}, cps, 0.0, cfg, pcfg, Lag{delay, time_constant});
      SCOPED_TRACE(::testing::Message() << "delay " << delay << " periods, time constant " << time_constant << " s");
      EXPECT_TRUE(run.finished);
      EXPECT_LE(run.max_deviation, 0.022);
      EXPECT_LE(run.final_error, 0.010);
      EXPECT_EQ(run.passed, 6);
      EXPECT_EQ(run.violations, 0);
    }
  }
}

// Logion's homologation path (config/logion.yaml): out of the start zone, down to (0.8, 0.4)
// over a last segment too short to take back the offset from the bend before it. The follower
// alone reaches the end along the tangent but beside it and stands there for ever (until the
// brain's timeout cancels it); the Autopilot must close that gap.
TEST(PathFollower, AnEndReachedBesideItIsStillReached) {
  const std::vector<Checkpoint> cps = {{0.5, 1.2}, {0.8, 0.7}, {0.8, 0.4}};
  for (int delay = 1; delay <= 4; ++delay) {
    for (double time_constant : {0.02, 0.05, 0.08, 0.12}) {
      const PathRun run = follow({0.55, 1.80, 0.0}, cps, 0.0, logionConfig(), logionPathConfig(), Lag{delay, time_constant});
      SCOPED_TRACE(::testing::Message() << "delay " << delay << " periods, time constant " << time_constant << " s");
      EXPECT_TRUE(run.finished);
      EXPECT_LE(run.final_error, 0.010);
      EXPECT_EQ(run.passed, 3);
      EXPECT_EQ(run.violations, 0);
    }
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

TEST(PathFollowerConfig, OutOfRangeValuesAreNamed) {
  EXPECT_TRUE(PathFollowerConfig().invalidReason().empty());
  PathFollowerConfig c;
  c.heading_correction_speed = -0.1;
  EXPECT_NE(c.invalidReason().find("heading_correction_speed"), std::string::npos);
  c = PathFollowerConfig();
  c.lookahead_time = 0.8;
  EXPECT_NE(c.invalidReason().find("lookahead_time"), std::string::npos);
  c = PathFollowerConfig();
  c.convergence_distance = 0.0;
  EXPECT_NE(c.invalidReason().find("convergence_distance"), std::string::npos);
}
