#include "hal_nodes/driver/driver_config.h"

#include <cmath>
#include <initializer_list>
#include <string>
#include <utility>

namespace hal_nodes {
namespace driver {

using robot_core::Params;

namespace {

ControlCurve readCurve(const Params& p) {
  ControlCurve c{p.requireDouble("saturation"), p.requireDouble("exponent")};
  p.requirePositive("saturation", c.saturation);
  p.requireInRange("exponent", c.exponent, 0.2, 4.0);
  return c;
}

// Optional numbers, each kept at its struct default when the block does not set it.
void readOptional(const Params& p, std::initializer_list<std::pair<const char*, double*>> fields) {
  for (const auto& f : fields) *f.second = p.optionalDouble(f.first, *f.second);
}

MotionLimits readLimits(const Params& p) {
  MotionLimits l;
  const std::pair<const char*, double*> fields[] = {
      {"max_linear_speed", &l.max_linear_speed}, {"max_angular_speed", &l.max_angular_speed},
      {"max_linear_accel", &l.max_linear_accel}, {"max_angular_accel", &l.max_angular_accel},
      {"max_wheel_speed", &l.max_wheel_speed},   {"track_width", &l.track_width}};
  for (const auto& f : fields) {
    *f.second = p.requireDouble(f.first);
    p.requirePositive(f.first, *f.second);
  }
  return l;
}

}  // namespace

AutopilotConfig readAutopilotConfig(const Params& p) {
  AutopilotConfig ap;
  ap.limits = readLimits(p["limits"]);
  ap.speed_curve = readCurve(p["speed_curve"]);
  ap.turn_curve = readCurve(p["turn_curve"]);
  ap.turn_in_place_angle = p.optionalDouble("turn_in_place_angle", 0.6);
  p.requireInRange("turn_in_place_angle", ap.turn_in_place_angle, 0.05, M_PI);
  ap.near_radius = p.optionalDouble("near_radius", 0.04);
  p.requireInRange("near_radius", ap.near_radius, 0.0, 0.5);
  p.check("", ap.invalidReason());
  return ap;
}

PathFollowerConfig readPathFollowerConfig(const Params& driver) {
  const Params p = driver["path"];
  PathFollowerConfig pf;
  readOptional(p, {{"convergence_distance", &pf.convergence_distance},
                   {"max_lateral_accel", &pf.max_lateral_accel},
                   {"sample_step", &pf.sample_step},
                   {"lookahead_time", &pf.lookahead_time},
                   {"heading_correction_speed", &pf.heading_correction_speed}});
  p.check("", pf.invalidReason());
  return pf;
}

AvoidanceConfig readAvoidanceConfig(const Params& driver, const AutopilotConfig& autopilot) {
  const Params p = driver["avoidance"];
  AvoidanceConfig av;
  const std::string mode = p.optionalString("mode", "stop");
  p.requireOneOf("mode", mode, {"off", "stop", "detour"});
  AvoidanceConfig::parseMode(mode, &av.mode);
  readOptional(p, {{"robot_radius", &av.robot_radius},
                   {"opponent_radius", &av.opponent_radius},
                   {"margin", &av.margin},
                   {"braking_distance", &av.braking_distance},
                   {"detection_distance", &av.detection_distance},
                   {"border_margin", &av.border_margin},
                   {"border_echo_tolerance", &av.border_echo_tolerance},
                   {"blocked_timeout", &av.blocked_timeout}});
  av.max_detours = p.optionalInt("max_detours", av.max_detours);
  p.check("", av.invalidReason());
  // The brake must be able to stop from full speed within braking_distance at the limit.
  const MotionLimits& l = autopilot.limits;
  const double stop_distance = l.max_linear_speed * l.max_linear_speed / (2.0 * l.max_linear_accel);
  if (av.mode != AvoidanceConfig::Mode::OFF && av.braking_distance < stop_distance)
    throw robot_core::ParameterError("parameter " + p.qualified("braking_distance") + " = " +
                                     std::to_string(av.braking_distance) +
                                     ": must be >= limits/max_linear_speed^2 / (2 limits/max_linear_accel) = " +
                                     std::to_string(stop_distance));
  return av;
}

DriverDeviceConfig readDriverDeviceConfig(const Params& p) {
  DriverDeviceConfig c;
  const std::pair<const char*, double*> positive[] = {
      {"default_position_tolerance", &c.default_position_tolerance},
      {"default_angle_tolerance", &c.default_angle_tolerance},
      {"default_straight_tolerance", &c.default_straight_tolerance},
      {"max_pose_age", &c.max_pose_age},
      {"max_odom_age", &c.max_odom_age}};
  for (const auto& f : positive) {
    *f.second = p.optionalDouble(f.first, *f.second);
    p.requirePositive(f.first, *f.second);
  }
  c.stall_timeout = p.optionalDouble("stall_timeout", c.stall_timeout);
  p.requireInRange("stall_timeout", c.stall_timeout, 0.0, 60.0);
  c.max_hold = p.optionalDouble("max_hold", c.max_hold);
  p.requireInRange("max_hold", c.max_hold, 0.0, 60.0);
  c.min_probability = p.optionalDouble("min_probability", c.min_probability);
  p.requireInRange("min_probability", c.min_probability, 0.0, 1.0);
  c.predict_pose = p.optionalBool("predict_pose", c.predict_pose);
  c.motor_status = p.optionalString("motor_status", c.motor_status);
  // diagnostic_updater names a status "<node name without its leading slash>: <task>".
  if (!c.motor_status.empty() && c.motor_status[0] == '/') c.motor_status.erase(0, 1);
  c.base_frame = p.optionalString("base_frame", c.base_frame);
  c.map_frame = p.optionalString("map_frame", c.map_frame);
  c.pose_topic = p.optionalString("pose_topic", c.pose_topic);
  c.quality_topic = p.optionalString("quality_topic", c.quality_topic);
  c.odom_topic = p.optionalString("odom_topic", c.odom_topic);
  c.cmd_vel_topic = p.optionalString("cmd_vel_topic", c.cmd_vel_topic);
  const Params a = p["avoidance"];
  c.detour_tolerance = a.optionalDouble("detour_tolerance", c.detour_tolerance);
  a.requirePositive("detour_tolerance", c.detour_tolerance);
  c.max_obstacle_age = a.optionalDouble("max_obstacle_age", c.max_obstacle_age);
  a.requirePositive("max_obstacle_age", c.max_obstacle_age);
  c.rangers = a.optionalStringList("rangers");
  c.ranger_prefix = a.optionalString("ranger_prefix", c.ranger_prefix);
  c.opponent_topic = a.optionalString("opponent_topic", c.opponent_topic);
  return c;
}

}  // namespace driver
}  // namespace hal_nodes
