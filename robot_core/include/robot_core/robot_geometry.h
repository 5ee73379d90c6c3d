// The robot's shape and drive as its description gives them: the robot: block of
// config/<robot>.yaml (/robot), which also draws the URDF. One reader of those values for every
// package that needs them (the HAL's drive, odometry, driver and localization, the simulated
// robot), so no other block carries a copy that could drift from it.
// A block may still set its own value: a test rig with no description, or a simulator that differs
// from the robot on purpose (the calibration's). blockOrDescribed() says which one a reader takes.
#pragma once

#include <optional>
#include <string>

#include "robot_core/params.h"

namespace robot_core {

struct RobotGeometry {
  std::optional<double> radius;          // [m] the footprint's circumscribed radius
  std::optional<double> wheel_radius;    // [m] the driven wheels
  std::optional<double> track_width;     // [m] between the driven wheels' contact points
  std::optional<double> encoder_ticks_per_rev;  // the driven wheels' encoders, per wheel revolution

  // The description's values from its block (/robot, or the robot block of a YAML file), each
  // > 0 where given; a value the description leaves out stays empty. Throws ParameterError.
  static RobotGeometry read(const Params& robot);
  // /robot of the parameter server (empty when there is none).
  static RobotGeometry fromParameterServer();

  // What a reader of `block` uses for `key`: the block's own value (> 0) where it sets one, else
  // the description's `described` (/robot/`described_key`), else `fallback` (which the reader
  // checks itself: a localization margin may be 0); throws
  // ParameterError naming both when none is there. Declared in the block's parameter table as
  // optional, its default the description's value.
  static double blockOrDescribed(const Params& block, const std::string& key, const std::optional<double>& described,
                                 const std::string& described_key, const std::string& meaning,
                                 const std::optional<double>& fallback = std::nullopt);
};

}  // namespace robot_core
