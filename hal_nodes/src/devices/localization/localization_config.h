// The Localization device's parameters (~ of /hal/localization, and the table from /table) read
// into one validated struct: the filter's, each input's and the outputs' settings. Every
// error is a ParameterError naming the parameter, as everywhere.
#pragma once

#include <ros/ros.h>
#include <robot_core/params.h>
#include <robot_core/robot_geometry.h>

#include <string>
#include <vector>

#include "hal_nodes/mcl/mcl.h"

namespace hal_nodes {
namespace localization {

struct LocalizationConfig {
  // The table (from /table) and what the robot's centre keeps away from.
  double table_length = 3.0, table_width = 2.1;  // [m]
  double robot_radius = 0.0;                     // [m] margin from the borders and obstacles
  std::vector<mcl::Rect> obstacles;              // fixed, [x0, y0, x1, y1]

  mcl::FilterConfig filter;

  // Advancing input: /odom alone, or encoder pairs averaged by reliability.
  mcl::MotionModel motion;
  std::string odom_topic = "/odom";
  std::vector<mcl::OdometryInput::Pair> pairs;  // empty: /odom alone
  std::vector<std::string> pair_topics;

  // Checking inputs (each off when its block disables or omits it).
  bool beacons_enabled = true;
  mcl::BeaconBeltsConfig beacons;
  std::string beacons_topic = "/hal/beacons/ranges";
  bool compass_enabled = false;
  mcl::CompassConfig compass;
  std::string compass_topic = "/hal/compass/heading";
  std::vector<mcl::RangerConfig> rangers;
  std::vector<std::string> ranger_topics;
  double rangers_reliability = 0.5;
  std::vector<mcl::BumperConfig> bumpers;
  mcl::BumpersOptions bumpers_options;
  std::string bumpers_topic = "/hal/bumpers/contacts";

  // Start: a pose with its spread, or none (global localization).
  std::vector<double> initial_pose;  // [x, y, theta] or empty
  double initial_std_xy = 0.02, initial_std_theta = 0.02;
  double save_pose_period = 2.0;     // [s] the estimate saved as ~initial_pose_* (0: never)
  double lost_error_after = 1.0;     // [s] lost this long: ERROR; before, a WARN while it re-localizes

  // Outputs and timing.
  std::string map_frame = "map", odom_frame = "odom", base_frame = "base_link";
  bool publish_tf = true;
  double transform_tolerance = 0.1;  // [s] the map -> odom transform is valid this long (as amcl)
  double latency = 0.05;             // [s] inputs wait this long behind the newest odometry
  double cloud_period = 0.2;         // [s] between particle clouds
};

// The device's own block (~, the device's configure()): everything but the table's part, which
// stays at its defaults. Throws ParameterError.
LocalizationConfig readLocalizationConfig(const robot_core::Params& device, const robot_core::RobotGeometry& robot);
// The table's part from /table (outside the device's block: read by the device's init()): its
// size and, with the beacons enabled, their positions; checks ~robot_radius (of `device`, read
// into `c` already) against the size. Throws ParameterError.
void readTableConfig(const robot_core::Params& table, const robot_core::Params& device, LocalizationConfig* c);
// Both (the device's block and /table of a YAML file: check_hal_config).
LocalizationConfig readLocalizationConfig(const robot_core::Params& device, const robot_core::Params& table,
                                          const robot_core::RobotGeometry& robot);

}  // namespace localization
}  // namespace hal_nodes
