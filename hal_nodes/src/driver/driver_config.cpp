#include "hal_nodes/driver/driver_config.h"

#include <cmath>
#include <initializer_list>
#include <string>
#include <utility>

#include "hal_nodes/described_number.h"

namespace hal_nodes {
namespace driver {

using robot_core::Params;

namespace {

// `saturation` is what the curve maps from: the speed curve's distance, the turn curve's angle.
ControlCurve readCurve(const Params& p, const char* saturation) {
  p.describe("saturation", saturation);
  p.describe("exponent", "shape below saturation: 1 proportional, < 1 more command near the goal, > 1 creeps in");
  ControlCurve c{p.requireDouble("saturation"), p.requireDouble("exponent")};
  p.requirePositive("saturation", c.saturation);
  p.requireInRange("exponent", c.exponent, 0.2, 4.0);
  return c;
}

// Optional numbers, each kept at its struct default when the block does not set it.
void readOptional(const Params& p, std::initializer_list<DescribedNumber> fields) {
  for (const auto& f : fields) {
    p.describe(f.name, f.meaning);
    *f.value = p.optionalDouble(f.name, *f.value);
  }
}

MotionLimits readLimits(const Params& p, const robot_core::RobotGeometry& robot) {
  MotionLimits l;
  const DescribedNumber fields[] = {
      {"max_linear_speed", &l.max_linear_speed, "[m/s] linear speed limit of every controlled command"},
      {"max_angular_speed", &l.max_angular_speed, "[rad/s] turn-rate limit of every controlled command"},
      {"max_linear_accel", &l.max_linear_accel, "[m/s^2] linear acceleration limit, also the deceleration"},
      {"max_angular_accel", &l.max_angular_accel, "[rad/s^2] angular acceleration limit"},
      {"max_wheel_speed", &l.max_wheel_speed, "[m/s] |v| + |w| * track_width / 2 never exceeds it"}};
  for (const auto& f : fields) {
    p.describe(f.name, f.meaning);
    *f.value = p.requireDouble(f.name);
    p.requirePositive(f.name, *f.value);
  }
  l.track_width = robot_core::RobotGeometry::blockOrDescribed(p, "track_width", robot.track_width, "track_width",
                                                              "[m] distance between the driven wheels");
  return l;
}

}  // namespace

AutopilotConfig readAutopilotConfig(const Params& p, const robot_core::RobotGeometry& robot) {
  AutopilotConfig ap;
  ap.limits = readLimits(p["limits"], robot);
  ap.speed_curve = readCurve(p["speed_curve"], "[m] distance to the goal from which the full speed is commanded");
  ap.turn_curve = readCurve(p["turn_curve"], "[rad] angular deviation from which the full turn rate is commanded");
  p.describe("turn_in_place_angle", "[rad] bearing error above which the robot turns on the spot without driving");
  ap.turn_in_place_angle = p.optionalDouble("turn_in_place_angle", 0.6);
  p.requireInRange("turn_in_place_angle", ap.turn_in_place_angle, 0.05, M_PI);
  p.describe("near_radius", "[m] within it, the distance is closed along the heading only, no steering to the point");
  ap.near_radius = p.optionalDouble("near_radius", 0.04);
  p.requireInRange("near_radius", ap.near_radius, 0.0, 0.5);
  p.check("", ap.invalidReason());
  return ap;
}

PathFollowerConfig readPathFollowerConfig(const Params& driver) {
  const Params p = driver["path"];
  PathFollowerConfig pf;
  readOptional(p, {{"convergence_distance", &pf.convergence_distance,
                    "[m] distance over which an offset from the curve is taken back"},
                   {"max_lateral_accel", &pf.max_lateral_accel,
                    "[m/s^2] speed in bends: v^2 * curvature stays under it"},
                   {"sample_step", &pf.sample_step, "[m] spacing of the curve's samples"},
                   {"lookahead_time", &pf.lookahead_time,
                    "[s] the curvature fed forward is taken this far ahead (the actuation lag)"},
                   {"heading_correction_speed", &pf.heading_correction_speed,
                    "[m/s] slower than this, heading errors are corrected as at this speed"}});
  p.check("", pf.invalidReason());
  return pf;
}

AvoidanceConfig readAvoidanceConfig(const Params& driver, const AutopilotConfig& autopilot,
                                    const robot_core::RobotGeometry& robot) {
  const Params p = driver["avoidance"];
  AvoidanceConfig av;
  p.describe("mode", "off; stop: brake and wait; detour: two waypoints beside the obstacle (else stop)");
  const std::string mode = p.optionalString("mode", "stop");
  p.requireOneOf("mode", mode, {"off", "stop", "detour"});
  AvoidanceConfig::parseMode(mode, &av.mode);
  av.robot_radius = robot_core::RobotGeometry::blockOrDescribed(
      p, "robot_radius", robot.radius, "radius", "[m] our footprint's circumscribed radius", av.robot_radius);
  readOptional(p, {{"opponent_radius", &av.opponent_radius, "[m] assumed size around an opponent point"},
                   {"margin", &av.margin, "[m] extra room kept around the opponent"},
                   {"braking_distance", &av.braking_distance,
                    "[m] the robot stops within this after a detection (>= the stop distance from full speed)"},
                   {"detection_distance", &av.detection_distance, "[m] how far ahead along the route to look"},
                   {"border_margin", &av.border_margin, "[m] echoes this close to the table edge are the border"},
                   {"border_echo_tolerance", &av.border_echo_tolerance,
                    "[m] a ranger echo this close to the border's range anywhere in its cone is the border"},
                   {"blocked_timeout", &av.blocked_timeout,
                    "[s] stopped this long for an obstacle: the goal is blocked (recoveries, then BLOCKED)"}});
  p.describe("max_detours", "detours per goal (mode detour); more: stop instead");
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
  const DescribedNumber positive[] = {
      {"default_position_tolerance", &c.default_position_tolerance,
       "[m] position tolerance of a goto or follow_path goal that gives none"},
      {"default_angle_tolerance", &c.default_angle_tolerance,
       "[rad] angle tolerance of a goto or rotate_by goal that gives none"},
      {"default_straight_tolerance", &c.default_straight_tolerance,
       "[m] tolerance of a go_straight goal that gives none"},
      {"max_pose_age", &c.max_pose_age, "[s] localization older than this holds a goto or follow_path goal"},
      {"max_odom_age", &c.max_odom_age, "[s] odometry older than this holds a go_straight or rotate_by goal"}};
  for (const auto& f : positive) {
    p.describe(f.name, f.meaning);
    *f.value = p.optionalDouble(f.name, *f.value);
    p.requirePositive(f.name, *f.value);
  }
  p.describe("stall_timeout", "[s] wheels commanded while odometry reads no motion this long: a stall (0: off)");
  c.stall_timeout = p.optionalDouble("stall_timeout", c.stall_timeout);
  p.requireInRange("stall_timeout", c.stall_timeout, 0.0, 60.0);
  p.describe("max_hold",
             "[s] a passing fault (stale or uncertain inputs, motor ERROR) lasting longer ends the goal; 0: at once");
  c.max_hold = p.optionalDouble("max_hold", c.max_hold);
  p.requireInRange("max_hold", c.max_hold, 0.0, 60.0);
  p.describe("min_probability", "localization less certain than this holds a goto or follow_path goal");
  c.min_probability = p.optionalDouble("min_probability", c.min_probability);
  p.requireInRange("min_probability", c.min_probability, 0.0, 1.0);
  p.describe("predict_pose", "carry the map pose from the newest odometry's stamp to now by its twist");
  c.predict_pose = p.optionalBool("predict_pose", c.predict_pose);
  p.describe("motor_status",
             "status-name prefix of the drive effector on /diagnostics: its ERROR holds the goal; '': ignored");
  c.motor_status = p.optionalString("motor_status", c.motor_status);
  // diagnostic_updater names a status "<node name without its leading slash>: <task>".
  if (!c.motor_status.empty() && c.motor_status[0] == '/') c.motor_status.erase(0, 1);
  p.describe("base_frame", "the robot's frame: the rangers are placed with tf from it");
  c.base_frame = p.optionalString("base_frame", c.base_frame);
  p.describe("map_frame", "the map frame (goals, the path, move_base's target_pose)");
  c.map_frame = p.optionalString("map_frame", c.map_frame);
  p.describe("pose_topic", "localization's pose in (geometry_msgs/PoseWithCovarianceStamped)");
  c.pose_topic = p.optionalString("pose_topic", c.pose_topic);
  p.describe("quality_topic", "localization's quality in (hal_nodes/LocalizationQuality)");
  c.quality_topic = p.optionalString("quality_topic", c.quality_topic);
  p.describe("odom_topic", "odometry in (nav_msgs/Odometry)");
  c.odom_topic = p.optionalString("odom_topic", c.odom_topic);
  p.describe("cmd_vel_topic", "velocity command out (geometry_msgs/Twist), only while a goal runs");
  c.cmd_vel_topic = p.optionalString("cmd_vel_topic", c.cmd_vel_topic);
  const Params a = p["avoidance"];
  a.describe("detour_tolerance", "[m] a detour waypoint counts as passed this close");
  c.detour_tolerance = a.optionalDouble("detour_tolerance", c.detour_tolerance);
  a.requirePositive("detour_tolerance", c.detour_tolerance);
  a.describe("max_obstacle_age", "[s] older ranger echoes and opponent positions are not obstacles");
  c.max_obstacle_age = a.optionalDouble("max_obstacle_age", c.max_obstacle_age);
  a.requirePositive("max_obstacle_age", c.max_obstacle_age);
  a.describe("rangers", "names on ranger_prefix whose echoes are obstacles");
  c.rangers = a.optionalStringList("rangers");
  a.describe("ranger_prefix", "topic prefix of the rangers (sensor_msgs/Range), also of recovery/rear_rangers");
  c.ranger_prefix = a.optionalString("ranger_prefix", c.ranger_prefix);
  a.describe("opponent_topic", "the tracked opponent in (geometry_msgs/PointStamped in the map); '': none");
  c.opponent_topic = a.optionalString("opponent_topic", c.opponent_topic);
  return c;
}

}  // namespace driver
}  // namespace hal_nodes
