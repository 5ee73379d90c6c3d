// Shared by the driver's gtests: the 2009 robot's and Logion's driver config, and a closed loop of a
// controller, the VelocityLimiter and the KinematicModel that records what a test asserts on.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "hal_nodes/driver/autopilot.h"
#include "hal_nodes/driver/driver_config.h"
#include "hal_nodes/driver/kinematic_model.h"
#include "hal_nodes/driver/motion_limits.h"

namespace hal_nodes {
namespace driver {
namespace test {

// The robots' own driver blocks (config/<robot>.yaml, hal: driver:), read as the device reads them.
inline AutopilotConfig configOf(const std::string& robot) {
  const std::string file = std::string(ROBOT_CONFIG_DIR) + "/" + robot + ".yaml";
  return readAutopilotConfig(robot_core::Params::fromYamlFile(file, "hal/driver"),
                             robot_core::RobotGeometry::read(robot_core::Params::fromYamlFile(file, "robot")));
}

// The 2009 robot's.
inline AutopilotConfig robotConfig() { return configOf("eurobot2009"); }

// Logion's: slower, with more actuation lag than the 2009 robot.
inline AutopilotConfig logionConfig() { return configOf("logion"); }

// Every command the limiter let through, checked against the limits as it is sent.
struct LimitWatch {
  explicit LimitWatch(const MotionLimits& l) : limits(l) {}
  void check(const Twist2D& prev, const Twist2D& cmd, double dt) {
    const double eps = 1e-9;
    if (std::fabs(cmd.v) > limits.max_linear_speed + eps) ++violations;
    if (std::fabs(cmd.w) > limits.max_angular_speed + eps) ++violations;
    if (std::fabs(cmd.v) + std::fabs(cmd.w) * limits.track_width / 2 > limits.max_wheel_speed + eps) ++violations;
    if (std::fabs(cmd.v - prev.v) > limits.max_linear_accel * dt + eps) ++violations;
    if (std::fabs(cmd.w - prev.w) > limits.max_angular_accel * dt + eps) ++violations;
    ++commands;
  }
  MotionLimits limits;
  int violations = 0;
  int commands = 0;
};

// Drive `step` (a controller's step(pose, last command)) until `done()` or max_time.
struct LoopResult {
  double time = 0.0;
  bool finished = false;
  int limit_violations = 0;
};

inline LoopResult closedLoop(KinematicModel& robot, const MotionLimits& limits, double dt, double max_time,
                             const std::function<Twist2D(const Pose2D&, const Twist2D&)>& step,
                             const std::function<bool()>& done,
                             const std::function<void(const KinematicModel&)>& observe = nullptr) {
  VelocityLimiter limiter(limits);
  LimitWatch watch(limits);
  LoopResult r;
  for (; r.time < max_time; r.time += dt) {
    const Twist2D desired = step(robot.pose(), limiter.last());
    if (done()) {
      r.finished = true;
      break;
    }
    const Twist2D prev = limiter.last();
    const Twist2D cmd = limiter.apply(desired, dt);
    watch.check(prev, cmd, dt);
    robot.step(cmd, dt);
    if (observe) observe(robot);
  }
  // Let the model come to rest (the command is zero now) before the caller measures.
  for (int i = 0; i < 50; ++i) robot.step(Twist2D(), dt);
  r.limit_violations = watch.violations;
  return r;
}

}  // namespace test
}  // namespace driver
}  // namespace hal_nodes
