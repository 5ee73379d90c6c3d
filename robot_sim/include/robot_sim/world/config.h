// The world's configuration as plain structs, read once at start from the parameter tree
// (`/table` for the table, `/sim/world` for everything simulated; schema documented in
// config/eurobot2009.sim.yaml). Plain structs so the models and their tests need no ROS master.
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "robot_sim/world/world.h"

namespace XmlRpc {
class XmlRpcValue;
}

#include <robot_core/parameter_error.h>
#include <robot_core/params.h>

namespace robot_sim {

// A bad parameter: what() is the one line naming the parameter and the allowed values (the
// error of robot_core's reader, which reads the world's tree).
using ConfigError = robot_core::ParameterError;

struct Point2D {
  double x = 0.0;
  double y = 0.0;
};

// An axis-aligned rectangle on the table (start zones, scoring zones).
struct Zone {
  std::string name;
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
  std::vector<std::string> kinds;  // element kinds that score here (empty: any)
  int points = 0;                  // per element lying inside
  // Whose points they are: a team colour (a start zone's name: that team), or "placer" (the
  // robot that last moved the element, e.g. the shared 2009 temple). Empty means "placer".
  std::string team;
  bool contains(double x, double y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};

struct TableConfig {
  double length = 3.0;
  double width = 2.1;
  double border_height = 0.07;
  std::vector<Point2D> beacons;  // ids 0..n-1
  std::vector<Zone> start_zones;
  std::vector<Zone> score_zones;
  std::vector<GameElement> elements;
};

struct MotorConfig {
  std::string drive;           // "left", "right" (a drive wheel) or "" (an auxiliary motor)
  double max_speed = 20.0;     // no-load output shaft speed at full command [rad/s]
  double time_constant = 0.05; // first-order lag [s]
  double dead_band = 0.0;      // fraction of full command the motor does not turn below (friction)
  double max_accel = 60.0;     // [rad/s^2]
  double stall_current = 6.0;  // [A] at full command, shaft blocked
  double current_limit = 4.0;  // [A] the H-bridge limits the current to this
  double no_load_current = 0.15;  // [A]
  bool inverted = false;       // a positive command turns the wheel backwards
};

struct EncoderConfig {
  std::string motor;           // driven: counts this motor's wheel (slip included)
  double y = 0.0;              // free (undriven measuring wheel): lateral offset [m], left +
  double radius = 0.0;         // free: measuring wheel radius [m]
  double ticks_per_rev = 512;  // per wheel revolution (quadrature edges included)
  int sign = 1;                // -1: counts down when the wheel rolls forward
  bool driven() const { return !motor.empty(); }
};

struct RangerConfig {
  std::string type = "srf02";  // srf02 | sharp
  Pose2D mount;                // in base_link
  double min_range = 0.03;
  double max_range = 6.0;
  double beam_width = 0.96;    // full cone angle [rad] (SRF02 ~55 deg)
  double noise_std = 0.01;     // [m]
  double noise_rel = 0.0;      // extra std per metre of range
  double bias = 0.0;           // [m] added to every reading (a sensor mounted off, a curve off)
  bool sees_elements = false;  // low rangers see game elements too
};

struct SwitchConfig {
  std::string type = "manual";  // bumper | limit | manual | element
  // bumper: closes when an obstacle touches the outline at a point whose direction from
  // base_link's origin is within +-span/2 of angle
  double angle = 0.0;
  double span = 1.0;
  // limit: closes when the actuator (stepper or servo) is at or beyond `at` in `direction`
  std::string actuator;
  double at = 0.0;
  int direction = -1;          // -1: closed at or below `at`; +1: at or above
  // element: closes when an element centre lies within `radius` of (x, y) in base_link
  double x = 0.0, y = 0.0, radius = 0.03;
  bool initially_closed = false;  // manual switches (start cord, colour selector)
};

struct ServoConfig {
  double min = -1.6, max = 1.6;  // [rad]
  double speed = 4.0;            // [rad/s]
  double initial = 0.0;
};

struct StepperConfig {
  int64_t min = -100000, max = 100000;
  double steps_per_second = 1000.0;
  int64_t initial = 0;
};

// Picks up elements of the given kinds whose centre enters the mouth while the motor runs
// forward (or the servo is beyond its threshold); ejects them in front when it runs backward.
struct CollectorConfig {
  double x = 0.15, y = 0.0, radius = 0.05;  // mouth in base_link
  std::vector<std::string> kinds;
  int capacity = 5;
  std::string motor;           // active while |command| > 0.1, ejects while command < -0.1
  double intake_time = 0.0;    // [s] a swallowed element stays at the mouth this long on its way in
                               // (under a throat sensor there, an element switch)
  // A gripper instead (the 2009 hand): no motor; it holds what is at its mouth while every
  // finger servo is within finger_tolerance of its closed angle, and lets go at the mouth when
  // a finger opens.
  std::vector<std::string> fingers;
  std::vector<double> finger_closed;   // [rad], one per finger
  double finger_tolerance = 0.2;       // [rad]
};

struct SlipConfig {
  double per_accel = 0.01;     // slip fraction per m/s^2 of wheel surface acceleration
  double noise_std = 0.002;    // random slip fraction per step (only while the wheel turns)
  double max = 0.5;
};

struct RobotConfig {
  Pose2D start{0.25, 0.25, 0.0};
  double radius = 0.15;        // the outline's radius when no footprint is given [m]
  // The outline in base_link: vertices [x, y] in order around it; empty: a regular 32-gon with
  // its vertices on `radius` (the URDF's chassis cylinder).
  std::vector<Point2D> footprint;
  double wheel_radius = 0.035;
  double wheel_base = 0.25;
  std::map<std::string, MotorConfig> motors;
  std::map<std::string, EncoderConfig> encoders;
  std::map<std::string, RangerConfig> rangers;
  std::map<std::string, SwitchConfig> switches;
  std::map<std::string, ServoConfig> servos;
  std::map<std::string, StepperConfig> steppers;
  std::map<std::string, CollectorConfig> collectors;
  SlipConfig slip;
};

struct CompassConfig {
  double north_deg = 90.0;     // direction of magnetic north in the map frame, CCW from +x [deg]
  double bias_deg = 2.0;
  double noise_std_deg = 1.0;
};

struct BeaconConfig {
  Point2D receiver;            // receiver position in base_link [m]
  double height_delta = 0.0;   // beacon height minus receiver height [m]
  double period = 0.15;        // one cycle of the three transmit slots [s]
  double speed_of_sound = 343.0;
  double noise_std = 20e-6;    // [s]
  double dropout = 0.02;       // probability a slot yields nothing
  double outlier = 0.01;       // probability of a uniform random delta instead
  double max_delta = 0.012;    // the receiver's window [s]
};

struct BatteryConfig {
  double full = 12.6;          // [V]
  double empty = 11.0;         // [V] after `life` seconds of average use
  double life = 3600.0;        // [s]
  double internal_resistance = 0.08;  // [ohm]
  double noise_std = 0.01;     // [V]
};

struct OpponentConfig {
  bool enabled = true;
  std::string mode = "random_walk";  // static | script | random_walk | player
  Pose2D start{2.75, 0.25, 3.14159265358979};
  double radius = 0.15;
  double speed = 0.3;          // [m/s]
  double turn_rate = 2.0;      // [rad/s]
  double pause = 1.0;          // [s] at each waypoint
  std::vector<Point2D> waypoints;  // script mode, looped
  double margin = 0.25;        // random walk stays this far from the borders
  // What its own sensors make it do: never closer to our outline than this [m]; blocked by us
  // this long [s], it backs off this far [m] and takes another target.
  double safety_distance = 0.05;
  double give_way_after = 2.0;
  double back_off = 0.15;
  // player: how many elements it carries at once (default: our robot's largest collector, the
  // robot it imitates) and how long taking or putting down takes [s].
  int player_capacity = 1;
  double player_handling_time = 1.0;
};

struct MatchConfig {
  std::string year = "2009";
  double duration = 90.0;      // [s] (the 2008 and 2009 rules)
  std::string start_switch;    // the match starts when this switch opens ("" : at t = 0)
};

struct WorldConfig {
  double dt = 0.001;           // integration step [s]
  unsigned seed = 1;
  TableConfig table;
  RobotConfig robot;
  CompassConfig compass;
  BeaconConfig beacons;
  BatteryConfig battery;
  OpponentConfig opponent;
  MatchConfig match;
};

// Reads `world` (the /sim/world dictionary), `table` (the /table dictionary) and `robot` (the
// /robot dictionary: the robot as built, config/<robot>.yaml). The simulated robot takes its
// geometry from `robot` (radius, footprint, wheel_radius, track_width as the wheel base, encoder_ticks_per_rev
// for the driven wheels' encoders, each ranger's mount from its link ranger_NAME) unless
// sim/world/robot sets its own value: a simulated robot that differs from its description on
// purpose (a calibration test's "true" robot, make calibrate's fitted simulator). The *_ns
// arguments are the resolved names, for error messages. Throws ConfigError.
WorldConfig parseWorldConfig(const XmlRpc::XmlRpcValue& world, const std::string& world_ns,
                             const XmlRpc::XmlRpcValue& table, const std::string& table_ns,
                             const XmlRpc::XmlRpcValue& robot = XmlRpc::XmlRpcValue(),
                             const std::string& robot_ns = "/robot");
// The same from readers already placed (Params::fromYamlFile of a robot's files in a test).
WorldConfig parseWorldConfig(const robot_core::Params& world, const robot_core::Params& table,
                             const robot_core::Params& robot = robot_core::Params());

}  // namespace robot_sim
