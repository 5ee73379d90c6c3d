// The Driver's controllers configured from its block (`hal: driver:` of config/<robot>.yaml):
// the one reader for the device (Params::of its node handle), its benchmark and its tests
// (Params::fromYamlFile of the robot's YAML), so none of them copies a robot's values by hand.
// Each returns a validated struct or throws robot_core::ParameterError naming the parameter.
#pragma once

#include <robot_core/params.h>

#include "hal_nodes/driver/autopilot.h"
#include "hal_nodes/driver/avoidance.h"
#include "hal_nodes/driver/path_follower.h"

namespace hal_nodes {
namespace driver {

// limits/*, speed_curve/*, turn_curve/*, turn_in_place_angle, near_radius.
AutopilotConfig readAutopilotConfig(const robot_core::Params& driver);
// path/*.
PathFollowerConfig readPathFollowerConfig(const robot_core::Params& driver);
// avoidance/* (the table's size comes from /table, read by the device); checks that the brake
// stops from full speed (the autopilot's limits) within braking_distance.
AvoidanceConfig readAvoidanceConfig(const robot_core::Params& driver, const AutopilotConfig& autopilot);

}  // namespace driver
}  // namespace hal_nodes
