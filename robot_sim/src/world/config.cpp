// Strict reading of the world's parameters: an unknown type or an out-of-range value throws
// ConfigError naming the parameter; a missing optional value takes the documented default.
#include "robot_sim/world/config.h"

#include <robot_core/params.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include "robot_sim/world/footprint.h"

#include <cmath>
#include <limits>
#include <optional>

namespace robot_sim {
namespace {

using robot_core::Params;

// The world's values read with robot_core's Params (the reader every layer uses) and its rules;
// these only name the checks the world needs, each failing with the one line naming the parameter.
[[noreturn]] void fail(const Params& n, const std::string& k, const std::string& what) {
  n.check(k, what);
  throw ConfigError("parameter " + n.ns() + ": " + what);  // check() always throws for a reason
}
double num(const Params& n, const std::string& k, double def) {
  const double v = n.optionalDouble(k, def);
  if (!std::isfinite(v)) fail(n, k, "must be a finite number");
  return v;
}
double positive(const Params& n, const std::string& k, double def) {
  const double v = num(n, k, def);
  n.requirePositive(k, v);
  return v;
}
double inRange(const Params& n, const std::string& k, double def, double lo, double hi) {
  const double v = num(n, k, def);
  n.requireInRange(k, v, lo, hi);
  return v;
}
double nonNegative(const Params& n, const std::string& k, double def) {
  return inRange(n, k, def, 0.0, std::numeric_limits<double>::infinity());
}
long integer(const Params& n, const std::string& k, long def) { return n.optionalInt(k, static_cast<int>(def)); }
bool boolean(const Params& n, const std::string& k, bool def) { return n.optionalBool(k, def); }
std::string str(const Params& n, const std::string& k, const std::string& def) { return n.optionalString(k, def); }
std::string oneOf(const Params& n, const std::string& k, const std::string& def, const std::vector<std::string>& allowed) {
  const std::string v = str(n, k, def);
  n.requireOneOf(k, v, allowed);
  return v;
}
std::vector<double> numbers(const Params& n, const std::string& k, std::size_t n_min, std::size_t n_max) {
  return n.optionalDoubleList(k, n_min, n_max);
}
std::vector<std::string> strings(const Params& n, const std::string& k) { return n.optionalStringList(k); }
// The named sub-dictionaries of a dictionary (motors, encoders, ...).
std::vector<std::pair<std::string, Params>> entries(const Params& n, const std::string& k) {
  std::vector<std::pair<std::string, Params>> out;
  for (const auto& name : n.blockNames(k)) out.emplace_back(name, n[k][name]);
  return out;
}
// A list of dictionaries (zones, elements).
std::vector<Params> items(const Params& n, const std::string& k) { return n.items(k); }
Pose2D pose(const Params& n, const std::string& k, Pose2D def) {
  auto v = numbers(n, k, 2, 3);
  if (v.empty()) return def;
  return Pose2D{v[0], v[1], v.size() > 2 ? v[2] : 0.0};
}

Zone parseZone(const Params& n) {
  Zone z;
  z.name = str(n, "name", "");
  auto r = numbers(n, "rect", 4, 4);
  if (r.empty()) fail(n, "rect", "is required: [x0, y0, x1, y1] in metres");
  z.x0 = std::min(r[0], r[2]);
  z.x1 = std::max(r[0], r[2]);
  z.y0 = std::min(r[1], r[3]);
  z.y1 = std::max(r[1], r[3]);
  z.kinds = strings(n, "kinds");
  z.points = static_cast<int>(integer(n, "points", 0));
  z.team = str(n, "team", "placer");
  return z;
}

TableConfig parseTable(const Params& n) {
  TableConfig t;
  t.length = positive(n, "length", 3.0);
  t.width = positive(n, "width", 2.1);
  t.border_height = positive(n, "border_height", 0.07);
  if (n.has("beacons")) {
    for (const auto& row : n.optionalDoubleRows("beacons", 2)) t.beacons.push_back({row[0], row[1]});
  } else {
    t.beacons = {{-0.062, -0.062}, {-0.062, t.width + 0.062}, {t.length + 0.062, t.width / 2.0}};
  }
  for (const auto& z : items(n, "start_zones")) t.start_zones.push_back(parseZone(z));
  for (const auto& z : items(n, "score_zones")) t.score_zones.push_back(parseZone(z));
  for (std::size_t i = 0; i < t.score_zones.size(); ++i) {
    const Zone& z = t.score_zones[i];
    bool known = z.team == "placer";
    for (const Zone& s : t.start_zones) known = known || s.name == z.team;
    if (!known) {
      std::string teams = "placer";
      for (const Zone& s : t.start_zones) teams += ", " + s.name;
      fail(items(n, "score_zones")[i], "team", "= '" + z.team + "': allowed values: " + teams +
                                                  " (a start zone's name is that team's colour)");
    }
  }
  for (const auto& e : items(n, "elements")) {
    GameElement g;
    g.kind = str(e, "kind", "");
    if (g.kind.empty()) fail(e, "kind", "is required (e.g. ball_red, ball_white, column)");
    g.pose = pose(e, "at", Pose2D{});
    if (!e.has("at")) fail(e, "at", "is required: [x, y] in metres");
    g.radius = positive(e, "radius", 0.035);
    g.height = positive(e, "height", 0.07);
    t.elements.push_back(g);
  }
  return t;
}

// A geometry value of the simulated robot: its own (sim/world/robot/KEY) where it sets one, else
// the robot's description (/robot/DESCRIBED), else the default.
double described(const Params& n, const std::string& key, const Params& robot, const std::string& described_key,
                 double def) {
  if (n.has(key)) return positive(n, key, def);
  return positive(robot, described_key, def);
}

// A ranger's mount [x, y, yaw] in base_link from its link ranger_NAME of the description
// (/robot/links/ranger_NAME/at: [x, y, z] or [x, y, z, roll, pitch, yaw], hung on base_link).
std::optional<Pose2D> describedMount(const Params& robot, const std::string& ranger) {
  const std::string link = "links/ranger_" + ranger;
  if (!robot.has(link)) return std::nullopt;
  const Params l = robot[link];
  const std::string parent = str(l, "parent", "base_link");
  if (parent != "base_link")
    fail(l, "parent", "= '" + parent + "': the simulator mounts a ranger on base_link; give " +
                          "sim/world/robot/rangers/" + ranger + "/mount instead");
  const auto at = numbers(l, "at", 3, 6);
  if (at.size() != 3 && at.size() != 6) fail(l, "at", "must be [x, y, z] or [x, y, z, roll, pitch, yaw]");
  return Pose2D{at[0], at[1], at.size() == 6 ? at[5] : 0.0};
}

RobotConfig parseRobot(const Params& n, const Params& robot) {
  RobotConfig r;
  r.start = pose(n, "start", r.start);
  r.radius = described(n, "radius", robot, "radius", r.radius);
  const Params& outline = n.has("footprint") ? n : robot;  // the simulated robot's own, else the description's
  if (outline.has("footprint")) {
    const auto rows = outline.optionalDoubleRows("footprint", 2);
    if (rows.size() < 3)
      fail(outline, "footprint", "must be a list of at least 3 vertices [x, y] in base_link, in order around the outline");
    for (const auto& row : rows) r.footprint.push_back({row[0], row[1]});
    try {
      Footprint check(r.footprint);
    } catch (const ConfigError& e) {
      fail(outline, "footprint", std::string(e.what()).substr(std::string("footprint: ").size()));
    }
  }
  r.wheel_radius = described(n, "wheel_radius", robot, "wheel_radius", r.wheel_radius);
  r.wheel_base = described(n, "wheel_base", robot, "track_width", r.wheel_base);
  for (const auto& [name, m] : entries(n, "motors")) {
    MotorConfig c;
    c.drive = oneOf(m, "drive", "", {"left", "right", ""});
    c.max_speed = positive(m, "max_speed", c.max_speed);
    c.time_constant = positive(m, "time_constant", c.time_constant);
    c.dead_band = inRange(m, "dead_band", c.dead_band, 0.0, 0.9);
    c.max_accel = positive(m, "max_accel", c.max_accel);
    c.stall_current = positive(m, "stall_current", c.stall_current);
    c.current_limit = positive(m, "current_limit", c.current_limit);
    c.no_load_current = nonNegative(m, "no_load_current", c.no_load_current);
    c.inverted = boolean(m, "inverted", false);
    r.motors[name] = c;
  }
  int left = 0, right = 0;
  for (const auto& [name, m] : r.motors) {
    left += m.drive == "left";
    right += m.drive == "right";
  }
  if (left != 1 || right != 1)
    fail(n, "motors", "needs exactly one motor with drive: left and one with drive: right");
  for (const auto& [name, e] : entries(n, "encoders")) {
    EncoderConfig c;
    c.motor = str(e, "motor", "");
    if (!c.motor.empty() && !r.motors.count(c.motor)) fail(e, "motor", "= '" + c.motor + "': not a motor under motors");
    if (c.motor.empty()) {
      if (!e.has("y") || !e.has("radius")) fail(e, "", "needs either motor (driven wheel) or y and radius (measuring wheel)");
      c.y = num(e, "y", 0.0);
      c.radius = positive(e, "radius", 0.03);
    }
    const bool driven_wheel = !c.motor.empty() && !r.motors[c.motor].drive.empty();
    c.ticks_per_rev = driven_wheel ? described(e, "ticks_per_rev", robot, "encoder_ticks_per_rev", 512)
                                   : positive(e, "ticks_per_rev", 512);
    c.sign = static_cast<int>(integer(e, "sign", 1));
    if (c.sign != 1 && c.sign != -1) fail(e, "sign", "allowed values: 1, -1");
    r.encoders[name] = c;
  }
  for (const auto& [name, g] : entries(n, "rangers")) {
    RangerConfig c;
    c.type = oneOf(g, "type", "srf02", {"srf02", "sharp"});
    const bool sharp = c.type == "sharp";
    c.mount = g.has("mount") ? pose(g, "mount", Pose2D{}) : describedMount(robot, name).value_or(Pose2D{});
    c.min_range = nonNegative(g, "min_range", sharp ? 0.10 : 0.03);
    c.max_range = positive(g, "max_range", sharp ? 0.80 : 6.0);
    if (c.max_range <= c.min_range) fail(g, "max_range", "must be > min_range");
    // The beam the HCL drivers report as field_of_view (SRF02: the datasheet's ~55 deg cone,
    // hcl_drivers srf02_registers.h; GP2D12: 0.08 rad, servo_board.cpp), so the localization and
    // the avoidance, which measure over the reported cone, expect the echo the sim makes.
    c.beam_width = inRange(g, "beam_width", sharp ? 0.08 : 0.96, 0.0, 3.0);
    c.noise_std = nonNegative(g, "noise_std", sharp ? 0.005 : 0.01);
    c.noise_rel = nonNegative(g, "noise_rel", sharp ? 0.03 : 0.0);
    c.bias = inRange(g, "bias", 0.0, -0.5, 0.5);
    c.sees_elements = boolean(g, "sees_elements", false);
    r.rangers[name] = c;
  }
  for (const auto& [name, s] : entries(n, "servos")) {
    ServoConfig c;
    c.min = num(s, "min", c.min);
    c.max = num(s, "max", c.max);
    if (c.max <= c.min) fail(s, "max", "must be > min");
    c.speed = positive(s, "speed", c.speed);
    c.initial = inRange(s, "initial", 0.5 * (c.min + c.max), c.min, c.max);
    r.servos[name] = c;
  }
  for (const auto& [name, s] : entries(n, "steppers")) {
    StepperConfig c;
    c.min = integer(s, "min", 0);
    c.max = integer(s, "max", 10000);
    if (c.max <= c.min) fail(s, "max", "must be > min");
    c.steps_per_second = positive(s, "steps_per_second", c.steps_per_second);
    c.initial = integer(s, "initial", c.min);
    if (c.initial < c.min || c.initial > c.max) fail(s, "initial", "must be within [min, max]");
    r.steppers[name] = c;
  }
  for (const auto& [name, s] : entries(n, "switches")) {
    SwitchConfig c;
    c.type = oneOf(s, "type", "", {"bumper", "limit", "manual", "element"});
    if (c.type == "bumper") {
      c.angle = num(s, "angle", 0.0);
      c.span = inRange(s, "span", 1.0, 0.0, 6.3);
    } else if (c.type == "limit") {
      c.actuator = str(s, "actuator", "");
      if (!r.steppers.count(c.actuator) && !r.servos.count(c.actuator))
        fail(s, "actuator", "= '" + c.actuator + "': must name a stepper or servo of this robot");
      c.at = num(s, "at", 0.0);
      c.direction = static_cast<int>(integer(s, "direction", -1));
      if (c.direction != 1 && c.direction != -1) fail(s, "direction", "allowed values: 1, -1");
    } else if (c.type == "element") {
      c.x = num(s, "x", 0.0);
      c.y = num(s, "y", 0.0);
      c.radius = positive(s, "radius", 0.03);
    }
    c.initially_closed = boolean(s, "closed", false);
    r.switches[name] = c;
  }
  for (const auto& [name, s] : entries(n, "collectors")) {
    CollectorConfig c;
    c.x = num(s, "x", c.x);
    c.y = num(s, "y", c.y);
    c.radius = positive(s, "radius", c.radius);
    c.kinds = strings(s, "kinds");
    c.capacity = static_cast<int>(integer(s, "capacity", c.capacity));
    c.motor = str(s, "motor", "");
    c.intake_time = inRange(s, "intake_time", c.intake_time, 0.0, 5.0);
    c.fingers = strings(s, "fingers");
    if (c.fingers.empty() == c.motor.empty())
      fail(s, "motor", "give either motor (a collector) or fingers + finger_closed (a gripper)");
    if (!c.motor.empty() && !r.motors.count(c.motor)) fail(s, "motor", "= '" + c.motor + "': must name a motor of this robot");
    for (const auto& f : c.fingers)
      if (!r.servos.count(f)) fail(s, "fingers", "= '" + f + "': must name servos of this robot");
    if (!c.fingers.empty()) {
      c.finger_closed = numbers(s, "finger_closed", c.fingers.size(), c.fingers.size());
      c.finger_tolerance = positive(s, "finger_tolerance", c.finger_tolerance);
    }
    r.collectors[name] = c;
  }
  const Params sl = n.block("slip");
  r.slip.per_accel = nonNegative(sl, "per_accel", r.slip.per_accel);
  r.slip.noise_std = nonNegative(sl, "noise_std", r.slip.noise_std);
  r.slip.max = inRange(sl, "max", r.slip.max, 0.0, 1.0);
  return r;
}

}  // namespace

WorldConfig parseWorldConfig(const XmlRpc::XmlRpcValue& world, const std::string& world_ns,
                             const XmlRpc::XmlRpcValue& table, const std::string& table_ns,
                             const XmlRpc::XmlRpcValue& robot, const std::string& robot_ns) {
  return parseWorldConfig(Params(world, world_ns), Params(table, table_ns), Params(robot, robot_ns));
}

WorldConfig parseWorldConfig(const Params& w, const Params& table, const Params& robot) {
  WorldConfig c;
  c.table = parseTable(table);
  c.dt = inRange(w, "dt", c.dt, 1e-4, 0.02);
  c.robot = parseRobot(w.block("robot"), robot);

  const Params cp = w.block("compass");
  c.compass.north_deg = num(cp, "north_deg", c.compass.north_deg);
  c.compass.bias_deg = num(cp, "bias_deg", c.compass.bias_deg);
  c.compass.noise_std_deg = nonNegative(cp, "noise_std_deg", c.compass.noise_std_deg);

  const Params b = w.block("beacons");
  auto rx = numbers(b, "receiver", 2, 2);
  if (!rx.empty()) c.beacons.receiver = {rx[0], rx[1]};
  c.beacons.height_delta = num(b, "height_delta", c.beacons.height_delta);
  c.beacons.period = positive(b, "period", c.beacons.period);
  c.beacons.speed_of_sound = positive(b, "speed_of_sound", c.beacons.speed_of_sound);
  c.beacons.noise_std = nonNegative(b, "noise_std", c.beacons.noise_std);
  c.beacons.dropout = inRange(b, "dropout", c.beacons.dropout, 0.0, 1.0);
  c.beacons.outlier = inRange(b, "outlier", c.beacons.outlier, 0.0, 1.0);
  c.beacons.max_delta = positive(b, "max_delta", c.beacons.max_delta);

  const Params bt = w.block("battery");
  c.battery.full = positive(bt, "full", c.battery.full);
  c.battery.empty = positive(bt, "empty", c.battery.empty);
  c.battery.life = positive(bt, "life", c.battery.life);
  c.battery.internal_resistance = nonNegative(bt, "internal_resistance", c.battery.internal_resistance);
  c.battery.noise_std = nonNegative(bt, "noise_std", c.battery.noise_std);

  const Params o = w.block("opponent");
  c.opponent.enabled = boolean(o, "enabled", c.opponent.enabled);
  c.opponent.mode = oneOf(o, "mode", c.opponent.mode, {"static", "script", "random_walk", "player"});
  c.opponent.start = pose(o, "start", Pose2D{c.table.length - 0.25, 0.25, M_PI});
  c.opponent.radius = positive(o, "radius", c.opponent.radius);
  c.opponent.speed = positive(o, "speed", c.opponent.speed);
  c.opponent.turn_rate = positive(o, "turn_rate", c.opponent.turn_rate);
  c.opponent.pause = nonNegative(o, "pause", c.opponent.pause);
  c.opponent.margin = nonNegative(o, "margin", c.opponent.margin);
  if (o.has("waypoints")) {
    for (const auto& row : o.optionalDoubleRows("waypoints", 2)) c.opponent.waypoints.push_back({row[0], row[1]});
  }
  c.opponent.safety_distance = nonNegative(o, "safety_distance", c.opponent.safety_distance);
  c.opponent.give_way_after = nonNegative(o, "give_way_after", c.opponent.give_way_after);
  c.opponent.back_off = nonNegative(o, "back_off", c.opponent.back_off);
  {
    int imitated = 1;  // the robot it imitates: ours
    for (const auto& kv : c.robot.collectors) imitated = std::max(imitated, kv.second.capacity);
    const Params p = o.block("player");
    c.opponent.player_capacity = static_cast<int>(integer(p, "capacity", imitated));
    p.requireInRange("capacity", c.opponent.player_capacity, 1, 100);
    c.opponent.player_handling_time = nonNegative(p, "handling_time", c.opponent.player_handling_time);
  }
  if (c.opponent.mode == "script" && c.opponent.waypoints.empty())
    fail(o, "waypoints", "mode script needs at least one waypoint");

  const Params m = w.block("match");
  c.match.year = oneOf(m, "year", c.match.year, {"2008", "2009"});
  c.match.duration = positive(m, "duration", c.match.duration);
  c.match.start_switch = str(m, "start_switch", "");
  if (!c.match.start_switch.empty() && !c.robot.switches.count(c.match.start_switch))
    fail(m, "start_switch", "= '" + c.match.start_switch + "': must name a switch under robot/switches");
  return c;
}

}  // namespace robot_sim
