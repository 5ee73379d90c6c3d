#include "robot_core/robot_geometry.h"

#include <ros/node_handle.h>

#include "robot_core/parameter_error.h"

namespace robot_core {

namespace {

std::optional<double> positiveIfGiven(const Params& robot, const std::string& key, const std::string& meaning) {
  robot.describe(key, meaning);
  if (!robot.has(key)) return std::nullopt;
  const double v = robot.requireDouble(key);
  robot.requirePositive(key, v);
  return v;
}

}  // namespace

RobotGeometry RobotGeometry::read(const Params& robot) {
  RobotGeometry g;
  g.radius = positiveIfGiven(robot, "radius", "[m] the footprint's circumscribed radius (the URDF's chassis)");
  g.wheel_radius = positiveIfGiven(robot, "wheel_radius", "[m] radius of the driven wheels");
  g.track_width = positiveIfGiven(robot, "track_width", "[m] between the driven wheels' contact points");
  g.encoder_ticks_per_rev =
      positiveIfGiven(robot, "encoder_ticks_per_rev", "the driven wheels' encoders: ticks per wheel revolution");
  return g;
}

RobotGeometry RobotGeometry::fromParameterServer() { return read(Params::of(ros::NodeHandle("/robot"))); }

double RobotGeometry::blockOrDescribed(const Params& block, const std::string& key,
                                       const std::optional<double>& described, const std::string& described_key,
                                       const std::string& meaning, const std::optional<double>& fallback) {
  const std::string from = "/robot/" + described_key;
  block.describe(key, meaning + "; set only where it differs from the description's " + from);
  const std::optional<double> otherwise = described ? described : fallback;
  if (!block.has(key) && !otherwise)
    throw ParameterError("parameter " + block.qualified(key) + ": not set, and the robot's description has no " + from);
  const double v = block.optionalDouble(key, otherwise.value_or(0.0), from);
  if (block.has(key) || described) block.requirePositive(key, v);  // the reader checks its own fallback
  return v;
}

}  // namespace robot_core
