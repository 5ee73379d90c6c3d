// The Driver's controllers configured from its block (`hal: driver:` of config/<robot>.yaml):
// the one reader for the device (Params::of its node handle), its benchmark and its tests
// (Params::fromYamlFile of the robot's YAML), so none of them copies a robot's values by hand.
// Each returns a validated struct or throws robot_core::ParameterError naming the parameter.
#pragma once

#include <robot_core/params.h>
#include <robot_core/robot_geometry.h>

#include <string>
#include <vector>

#include "hal_nodes/driver/autopilot.h"
#include "hal_nodes/driver/avoidance.h"
#include "hal_nodes/driver/path_follower.h"

namespace hal_nodes {
namespace driver {

// limits/*, speed_curve/*, turn_curve/*, turn_in_place_angle, near_radius; the track width from
// the robot's description unless limits/track_width sets one.
AutopilotConfig readAutopilotConfig(const robot_core::Params& driver, const robot_core::RobotGeometry& robot);
// path/*.
PathFollowerConfig readPathFollowerConfig(const robot_core::Params& driver);
// avoidance/* (the table's size comes from /table, read by the device; our radius from the robot's
// description unless avoidance/robot_radius sets one); checks that the brake
// stops from full speed (the autopilot's limits) within braking_distance.
AvoidanceConfig readAvoidanceConfig(const robot_core::Params& driver, const AutopilotConfig& autopilot,
                                    const robot_core::RobotGeometry& robot);

// What the Driver device needs besides its controllers: goal defaults, how old an input may be,
// the passing-fault and stall policy, its frames and topics.
struct DriverDeviceConfig {
  double default_position_tolerance = 0.01;   // [m] a goto goal without its own
  double default_angle_tolerance = 0.035;     // [rad] goto / rotate_by
  double default_straight_tolerance = 0.005;  // [m] go_straight
  double max_pose_age = 0.5;                  // [s] localization older: held
  double max_odom_age = 0.2;                  // [s] odometry older: held
  double min_probability = 0.5;               // localization less certain: held
  double max_hold = 5.0;                      // [s] a fault lasting longer ends the goal (0: at once)
  double stall_timeout = 1.0;                 // [s] commanded but not moving this long: BLOCKED (0: off)
  bool predict_pose = true;                   // carry the map pose from the odometry stamp to now
  std::string motor_status = "hal/drive:";    // status-name prefix of the drive effector ("": ignore)
  std::string base_frame = "base_link", map_frame = "map";
  std::string pose_topic = "/mcl/pose", quality_topic = "/mcl/quality", odom_topic = "/odom";
  std::string cmd_vel_topic = "/hal/drive/cmd_vel";
  // avoidance/
  double detour_tolerance = 0.05;  // [m] a detour waypoint counts as passed this close
  double max_obstacle_age = 0.3;   // [s] older echoes are not obstacles
  std::vector<std::string> rangers;  // names on ranger_prefix whose echoes are obstacles
  std::string ranger_prefix = "/hal/rangers/", opponent_topic;
};
DriverDeviceConfig readDriverDeviceConfig(const robot_core::Params& driver);

}  // namespace driver
}  // namespace hal_nodes
