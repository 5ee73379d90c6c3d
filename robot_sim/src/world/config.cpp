// Strict reading of the world's parameters: an unknown type or an out-of-range value throws
// ConfigError naming the parameter; a missing optional value takes the documented default.
// Each read is described beside it (the table: robot_sim/PARAMETERS.md, make docs).
#include "robot_sim/world/config.h"

#include <robot_core/params.h>
#include <robot_core/robot_geometry.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include "robot_sim/world/footprint.h"

#include <cmath>
#include <limits>
#include <optional>

namespace robot_sim {
namespace {

using robot_core::Params;
using robot_core::RobotGeometry;

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
  n.describe("name", "the zone's name (a start zone's: its team's colour)");
  z.name = str(n, "name", "");
  n.describe("rect", "[m] [x0, y0, x1, y1] the zone's rectangle in map");
  auto r = numbers(n, "rect", 4, 4);
  if (r.empty()) fail(n, "rect", "is required: [x0, y0, x1, y1] in metres");
  z.x0 = std::min(r[0], r[2]);
  z.x1 = std::max(r[0], r[2]);
  z.y0 = std::min(r[1], r[3]);
  z.y1 = std::max(r[1], r[3]);
  n.describe("kinds", "element kinds that score here (empty: any)");
  z.kinds = strings(n, "kinds");
  n.describe("points", "points per element lying inside");
  z.points = static_cast<int>(integer(n, "points", 0));
  n.describe("team", "whose points: a team colour (a start zone's name) or placer (the robot that last moved it)");
  z.team = str(n, "team", "placer");
  return z;
}

TableConfig parseTable(const Params& n) {
  TableConfig t;
  n.describe("length", "[m] the table's length along x of map");
  t.length = positive(n, "length", 3.0);
  n.describe("width", "[m] the table's width along y of map");
  t.width = positive(n, "width", 2.1);
  n.describe("border_height", "[m] height of the table's borders (drawn on /sim/markers)");
  t.border_height = positive(n, "border_height", 0.07);
  if (n.has("beacons")) {
    n.describe("beacons", "[m] the beacons' positions [[x, y], ..] in map, ids 0..n-1");
    for (const auto& row : n.optionalDoubleRows("beacons", 2)) t.beacons.push_back({row[0], row[1]});
  } else {
    t.beacons = {{-0.062, -0.062}, {-0.062, t.width + 0.062}, {t.length + 0.062, t.width / 2.0}};
  }
  n.describe("start_zones", "the start zones, one per team: {name (the team's colour), rect}");
  for (const auto& z : items(n, "start_zones")) t.start_zones.push_back(parseZone(z));
  n.describe("score_zones", "the scoring zones: {name, rect, kinds, points, team}");
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
  n.describe("elements", "the game elements on the table at t = 0: {kind, at, radius, height}");
  for (const auto& e : items(n, "elements")) {
    GameElement g;
    e.describe("kind", "the element's kind (e.g. ball_red, ball_white, column)");
    g.kind = str(e, "kind", "");
    if (g.kind.empty()) fail(e, "kind", "is required (e.g. ball_red, ball_white, column)");
    e.describe("at", "[m] [x, y] the element's position in map at t = 0");
    g.pose = pose(e, "at", Pose2D{});
    if (!e.has("at")) fail(e, "at", "is required: [x, y] in metres");
    e.describe("radius", "[m] the element's radius");
    g.radius = positive(e, "radius", 0.035);
    e.describe("height", "[m] the element's height");
    g.height = positive(e, "height", 0.07);
    t.elements.push_back(g);
  }
  return t;
}


// A ranger's mount [x, y, yaw] in base_link from its link ranger_NAME of the description
// (/robot/links/ranger_NAME/at: [x, y, z] or [x, y, z, roll, pitch, yaw], hung on base_link).
std::optional<Pose2D> describedMount(const Params& robot, const std::string& ranger) {
  const std::string link = "links/ranger_" + ranger;
  if (!robot.has(link)) return std::nullopt;
  const Params l = robot[link];
  l.describe("parent", "the link the ranger hangs on (the simulator mounts rangers on base_link)");
  const std::string parent = str(l, "parent", "base_link");
  if (parent != "base_link")
    fail(l, "parent", "= '" + parent + "': the simulator mounts a ranger on base_link; give " +
                          "sim/world/robot/rangers/" + ranger + "/mount instead");
  l.describe("at", "[m, rad] the ranger's mount [x, y, z] or [x, y, z, roll, pitch, yaw] in base_link");
  const auto at = numbers(l, "at", 3, 6);
  if (at.size() != 3 && at.size() != 6) fail(l, "at", "must be [x, y, z] or [x, y, z, roll, pitch, yaw]");
  return Pose2D{at[0], at[1], at.size() == 6 ? at[5] : 0.0};
}

RobotConfig parseRobot(const Params& n, const Params& robot) {
  // A geometry value of the simulated robot: its own (sim/world/robot/KEY) where it sets one, else
  // the robot's description, else the default.
  const RobotGeometry described = RobotGeometry::read(robot);
  RobotConfig r;
  n.describe("start", "[m, m, rad] the robot's pose [x, y, theta] in map at t = 0");
  r.start = pose(n, "start", r.start);
  r.radius = RobotGeometry::blockOrDescribed(
      n, "radius", described.radius, "radius",
      "[m] the outline's radius when no footprint is given (the URDF's chassis cylinder)", r.radius);
  const Params& outline = n.has("footprint") ? n : robot;  // the simulated robot's own, else the description's
  if (outline.has("footprint")) {
    const std::string outline_meaning = "[m] the outline [[x, y], ..] in base_link, vertices in order around it";
    outline.describe("footprint",
                     &outline == &n ? outline_meaning + "; else the description's footprint" : outline_meaning);
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
  r.wheel_radius = RobotGeometry::blockOrDescribed(n, "wheel_radius", described.wheel_radius, "wheel_radius",
                                                  "[m] radius of the two driven wheels", r.wheel_radius);
  r.wheel_base = RobotGeometry::blockOrDescribed(n, "wheel_base", described.track_width, "track_width",
                                                "[m] distance between the two driven wheels' contact points",
                                                r.wheel_base);
  n.describe("motors", "the motors by name: exactly one with drive: left and one with drive: right, others auxiliary");
  for (const auto& [name, m] : entries(n, "motors")) {
    MotorConfig c;
    m.describe("drive", "left or right: drives that wheel; empty: an auxiliary motor");
    c.drive = oneOf(m, "drive", "", {"left", "right", ""});
    m.describe("max_speed", "[rad/s] no-load output shaft speed at full command");
    c.max_speed = positive(m, "max_speed", c.max_speed);
    m.describe("time_constant", "[s] first-order lag of the shaft speed");
    c.time_constant = positive(m, "time_constant", c.time_constant);
    m.describe("dead_band", "[fraction of full command] a command below this does not turn it (friction)");
    c.dead_band = inRange(m, "dead_band", c.dead_band, 0.0, 0.9);
    m.describe("max_accel", "[rad/s^2] the shaft's largest acceleration");
    c.max_accel = positive(m, "max_accel", c.max_accel);
    m.describe("stall_current", "[A] current at full command with the shaft blocked");
    c.stall_current = positive(m, "stall_current", c.stall_current);
    m.describe("current_limit", "[A] the H-bridge limits the current to this");
    c.current_limit = positive(m, "current_limit", c.current_limit);
    m.describe("no_load_current", "[A] current of the running motor without load");
    c.no_load_current = nonNegative(m, "no_load_current", c.no_load_current);
    m.describe("inverted", "a positive command turns the wheel backwards");
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
  n.describe("encoders", "the encoders by name: of a driven wheel (motor) or of a measuring wheel (y, radius)");
  for (const auto& [name, e] : entries(n, "encoders")) {
    EncoderConfig c;
    e.describe("motor", "the motor whose wheel it counts, slip included; empty: a measuring wheel (y and radius)");
    c.motor = str(e, "motor", "");
    if (!c.motor.empty() && !r.motors.count(c.motor)) fail(e, "motor", "= '" + c.motor + "': not a motor under motors");
    if (c.motor.empty()) {
      if (!e.has("y") || !e.has("radius")) fail(e, "", "needs either motor (driven wheel) or y and radius (measuring wheel)");
      e.describe("y", "[m] lateral offset of the undriven measuring wheel, left +");
      c.y = num(e, "y", 0.0);
      e.describe("radius", "[m] radius of the undriven measuring wheel (it counts the ground)");
      c.radius = positive(e, "radius", 0.03);
    }
    const bool driven_wheel = !c.motor.empty() && !r.motors[c.motor].drive.empty();
    const std::string ticks = "ticks per wheel revolution, quadrature edges included";
    if (!driven_wheel) e.describe("ticks_per_rev", ticks);
    c.ticks_per_rev = driven_wheel ? RobotGeometry::blockOrDescribed(e, "ticks_per_rev", described.encoder_ticks_per_rev,
                                                                     "encoder_ticks_per_rev", ticks, 512.0)
                                   : positive(e, "ticks_per_rev", 512);
    e.describe("sign", "1, or -1: counts down when the wheel rolls forward");
    c.sign = static_cast<int>(integer(e, "sign", 1));
    if (c.sign != 1 && c.sign != -1) fail(e, "sign", "allowed values: 1, -1");
    r.encoders[name] = c;
  }
  n.describe("rangers", "the range sensors by name; nothing in range reads +inf");
  for (const auto& [name, g] : entries(n, "rangers")) {
    RangerConfig c;
    g.describe("type", "srf02 (ultrasound) or sharp (GP2D12 infrared): the other keys' defaults follow it");
    c.type = oneOf(g, "type", "srf02", {"srf02", "sharp"});
    const bool sharp = c.type == "sharp";
    if (g.has("mount"))
      g.describe("mount", "[m, m, rad] [x, y, theta] in base_link; else the description's link ranger_<name>");
    c.mount = g.has("mount") ? pose(g, "mount", Pose2D{}) : describedMount(robot, name).value_or(Pose2D{});
    g.describe("min_range", "[m] a nearer reading reads this");
    c.min_range = nonNegative(g, "min_range", sharp ? 0.10 : 0.03);
    g.describe("max_range", "[m] nothing beyond this comes back (+inf)");
    c.max_range = positive(g, "max_range", sharp ? 0.80 : 6.0);
    if (c.max_range <= c.min_range) fail(g, "max_range", "must be > min_range");
    // The beam the HCL drivers report as field_of_view (SRF02: the datasheet's ~55 deg cone,
    // hcl_drivers srf02_registers.h; GP2D12: 0.08 rad, servo_board.cpp), so the localization and
    // the avoidance, which measure over the reported cone, expect the echo the sim makes.
    g.describe("beam_width", "[rad] full cone angle: the nearest echo anywhere in it is the reading");
    c.beam_width = inRange(g, "beam_width", sharp ? 0.08 : 0.96, 0.0, 3.0);
    g.describe("noise_std", "[m] standard deviation of a reading");
    c.noise_std = nonNegative(g, "noise_std", sharp ? 0.005 : 0.01);
    g.describe("noise_rel", "[m per m] extra standard deviation per metre of range");
    c.noise_rel = nonNegative(g, "noise_rel", sharp ? 0.03 : 0.0);
    g.describe("bias", "[m] added to every reading (a sensor mounted off, a curve off)");
    c.bias = inRange(g, "bias", 0.0, -0.5, 0.5);
    g.describe("sees_elements", "a low ranger: sees the game elements too, not only borders and the opponent");
    c.sees_elements = boolean(g, "sees_elements", false);
    r.rangers[name] = c;
  }
  n.describe("servos", "the servos by name");
  for (const auto& [name, s] : entries(n, "servos")) {
    ServoConfig c;
    s.describe("min", "[rad] the lower end of its travel");
    c.min = num(s, "min", c.min);
    s.describe("max", "[rad] the upper end of its travel");
    c.max = num(s, "max", c.max);
    if (c.max <= c.min) fail(s, "max", "must be > min");
    s.describe("speed", "[rad/s] how fast it moves to its target");
    c.speed = positive(s, "speed", c.speed);
    s.describe("initial", "[rad] its position at t = 0");
    c.initial = inRange(s, "initial", 0.5 * (c.min + c.max), c.min, c.max);
    r.servos[name] = c;
  }
  n.describe("steppers", "the stepper motors by name");
  for (const auto& [name, s] : entries(n, "steppers")) {
    StepperConfig c;
    s.describe("min", "[steps] the lower end of its travel");
    c.min = integer(s, "min", 0);
    s.describe("max", "[steps] the upper end of its travel");
    c.max = integer(s, "max", 10000);
    if (c.max <= c.min) fail(s, "max", "must be > min");
    s.describe("steps_per_second", "[steps/s] how fast it moves to its target");
    c.steps_per_second = positive(s, "steps_per_second", c.steps_per_second);
    s.describe("initial", "[steps] its position at t = 0");
    c.initial = integer(s, "initial", c.min);
    if (c.initial < c.min || c.initial > c.max) fail(s, "initial", "must be within [min, max]");
    r.steppers[name] = c;
  }
  n.describe("switches", "the switches by name: bumpers, limit switches, manual switches and element switches");
  for (const auto& [name, s] : entries(n, "switches")) {
    SwitchConfig c;
    s.describe("type", "bumper (outline contact), limit (actuator position), manual (/sim/set_switch) or element");
    c.type = oneOf(s, "type", "", {"bumper", "limit", "manual", "element"});
    if (c.type == "bumper") {
      s.describe("angle", "[rad] bumper: the direction of the contacts it feels, from base_link's origin");
      c.angle = num(s, "angle", 0.0);
      s.describe("span", "[rad] bumper: closes when the outline touches an obstacle within angle +- span/2");
      c.span = inRange(s, "span", 1.0, 0.0, 6.3);
    } else if (c.type == "limit") {
      s.describe("actuator", "limit: the stepper or servo whose position closes it");
      c.actuator = str(s, "actuator", "");
      if (!r.steppers.count(c.actuator) && !r.servos.count(c.actuator))
        fail(s, "actuator", "= '" + c.actuator + "': must name a stepper or servo of this robot");
      s.describe("at", "[steps or rad] limit: the actuator position where it closes");
      c.at = num(s, "at", 0.0);
      s.describe("direction", "limit: -1 closed at or below at, +1 at or above");
      c.direction = static_cast<int>(integer(s, "direction", -1));
      if (c.direction != 1 && c.direction != -1) fail(s, "direction", "allowed values: 1, -1");
    } else if (c.type == "element") {
      s.describe("x", "[m] element: x in base_link of the spot it watches");
      c.x = num(s, "x", 0.0);
      s.describe("y", "[m] element: y in base_link of the spot it watches");
      c.y = num(s, "y", 0.0);
      s.describe("radius", "[m] element: closes when an element centre lies within this of (x, y)");
      c.radius = positive(s, "radius", 0.03);
    }
    s.describe("closed", "closed at t = 0 (a manual switch: start cord, colour; /sim/set_switch toggles it)");
    c.initially_closed = boolean(s, "closed", false);
    r.switches[name] = c;
  }
  n.describe("collectors", "the collectors (a motor) and grippers (fingers) taking game elements, by name");
  for (const auto& [name, s] : entries(n, "collectors")) {
    CollectorConfig c;
    s.describe("x", "[m] x of the mouth's centre in base_link");
    c.x = num(s, "x", c.x);
    s.describe("y", "[m] y of the mouth's centre in base_link");
    c.y = num(s, "y", c.y);
    s.describe("radius", "[m] the mouth's radius: it takes an element whose centre enters it");
    c.radius = positive(s, "radius", c.radius);
    s.describe("kinds", "element kinds it takes (empty: any)");
    c.kinds = strings(s, "kinds");
    s.describe("capacity", "how many elements it holds at once");
    c.capacity = static_cast<int>(integer(s, "capacity", c.capacity));
    s.describe("motor", "a collector's motor: swallows at the mouth while it runs forward, ejects while backward");
    c.motor = str(s, "motor", "");
    s.describe("intake_time", "[s] a swallowed element stays at the mouth this long (a throat sensor sees it)");
    c.intake_time = inRange(s, "intake_time", c.intake_time, 0.0, 5.0);
    s.describe("fingers", "a gripper's finger servos: holds what is at the mouth while they are closed");
    c.fingers = strings(s, "fingers");
    if (c.fingers.empty() == c.motor.empty())
      fail(s, "motor", "give either motor (a collector) or fingers + finger_closed (a gripper)");
    if (!c.motor.empty() && !r.motors.count(c.motor)) fail(s, "motor", "= '" + c.motor + "': must name a motor of this robot");
    for (const auto& f : c.fingers)
      if (!r.servos.count(f)) fail(s, "fingers", "= '" + f + "': must name servos of this robot");
    if (!c.fingers.empty()) {
      s.describe("finger_closed", "[rad] each finger's closed angle, in the order of fingers");
      c.finger_closed = numbers(s, "finger_closed", c.fingers.size(), c.fingers.size());
      s.describe("finger_tolerance", "[rad] a finger within this of its closed angle counts as closed");
      c.finger_tolerance = positive(s, "finger_tolerance", c.finger_tolerance);
    }
    r.collectors[name] = c;
  }
  const Params sl = n.block("slip");
  sl.describe("per_accel", "[fraction per m/s^2] wheel slip per unit of wheel surface acceleration");
  r.slip.per_accel = nonNegative(sl, "per_accel", r.slip.per_accel);
  sl.describe("noise_std", "[fraction] random slip per step, while the wheel turns");
  r.slip.noise_std = nonNegative(sl, "noise_std", r.slip.noise_std);
  sl.describe("max", "[fraction] the largest slip");
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
  w.describe("dt", "[s] the integration step");
  c.dt = inRange(w, "dt", c.dt, 1e-4, 0.02);
  c.robot = parseRobot(w.block("robot"), robot);

  const Params cp = w.block("compass");
  cp.describe("north_deg", "[deg] the direction of magnetic north in map, CCW from +x");
  c.compass.north_deg = num(cp, "north_deg", c.compass.north_deg);
  cp.describe("bias_deg", "[deg] added to every heading the compass reports");
  c.compass.bias_deg = num(cp, "bias_deg", c.compass.bias_deg);
  cp.describe("noise_std_deg", "[deg] standard deviation of a reported heading");
  c.compass.noise_std_deg = nonNegative(cp, "noise_std_deg", c.compass.noise_std_deg);

  const Params b = w.block("beacons");
  b.describe("receiver", "[m] [x, y] the beacon receiver's position in base_link");
  auto rx = numbers(b, "receiver", 2, 2);
  if (!rx.empty()) c.beacons.receiver = {rx[0], rx[1]};
  b.describe("height_delta", "[m] the beacons' height minus the receiver's");
  c.beacons.height_delta = num(b, "height_delta", c.beacons.height_delta);
  b.describe("period", "[s] one cycle of the three transmit slots");
  c.beacons.period = positive(b, "period", c.beacons.period);
  b.describe("speed_of_sound", "[m/s] as the HAL's beacon equation has it (343.21 at hal/beacons/temperature 20 C)");
  c.beacons.speed_of_sound = positive(b, "speed_of_sound", c.beacons.speed_of_sound);
  b.describe("noise_std", "[s] standard deviation of a measured delta");
  c.beacons.noise_std = nonNegative(b, "noise_std", c.beacons.noise_std);
  b.describe("dropout", "probability that a slot yields nothing");
  c.beacons.dropout = inRange(b, "dropout", c.beacons.dropout, 0.0, 1.0);
  b.describe("outlier", "probability of a uniform random delta instead of the measured one");
  c.beacons.outlier = inRange(b, "outlier", c.beacons.outlier, 0.0, 1.0);
  b.describe("max_delta", "[s] the receiver's window: a longer delta is not reported");
  c.beacons.max_delta = positive(b, "max_delta", c.beacons.max_delta);

  const Params bt = w.block("battery");
  bt.describe("full", "[V] open-circuit voltage of the charged battery");
  c.battery.full = positive(bt, "full", c.battery.full);
  bt.describe("empty", "[V] open-circuit voltage after life seconds of average use");
  c.battery.empty = positive(bt, "empty", c.battery.empty);
  bt.describe("life", "[s] time of average use from full to empty");
  c.battery.life = positive(bt, "life", c.battery.life);
  bt.describe("internal_resistance", "[ohm] the voltage drops by this times the motors' total current");
  c.battery.internal_resistance = nonNegative(bt, "internal_resistance", c.battery.internal_resistance);
  bt.describe("noise_std", "[V] standard deviation of a reported voltage");
  c.battery.noise_std = nonNegative(bt, "noise_std", c.battery.noise_std);

  const Params o = w.block("opponent");
  o.describe("enabled", "an opponent robot is on the table");
  c.opponent.enabled = boolean(o, "enabled", c.opponent.enabled);
  o.describe("mode", "static, script (drives the waypoints), random_walk or player (plays for the other colour)");
  c.opponent.mode = oneOf(o, "mode", c.opponent.mode, {"static", "script", "random_walk", "player"});
  o.describe("start", "[m, m, rad] the opponent's pose [x, y, theta] in map at t = 0");
  c.opponent.start = pose(o, "start", Pose2D{c.table.length - 0.25, 0.25, M_PI});
  o.describe("radius", "[m] the opponent's round outline");
  c.opponent.radius = positive(o, "radius", c.opponent.radius);
  o.describe("speed", "[m/s] the opponent's driving speed");
  c.opponent.speed = positive(o, "speed", c.opponent.speed);
  o.describe("turn_rate", "[rad/s] the opponent's largest turning rate");
  c.opponent.turn_rate = positive(o, "turn_rate", c.opponent.turn_rate);
  o.describe("pause", "[s] the opponent waits this long at each waypoint");
  c.opponent.pause = nonNegative(o, "pause", c.opponent.pause);
  o.describe("margin", "[m] the random walk stays this far from the borders");
  c.opponent.margin = nonNegative(o, "margin", c.opponent.margin);
  if (o.has("waypoints")) {
    o.describe("waypoints", "[m] [[x, y], ..] in map the script mode drives, looped");
    for (const auto& row : o.optionalDoubleRows("waypoints", 2)) c.opponent.waypoints.push_back({row[0], row[1]});
  }
  o.describe("safety_distance", "[m] the opponent never comes closer to our robot's outline (its own sensors)");
  c.opponent.safety_distance = nonNegative(o, "safety_distance", c.opponent.safety_distance);
  o.describe("give_way_after", "[s] blocked by our robot this long, the opponent backs off and takes another target");
  c.opponent.give_way_after = nonNegative(o, "give_way_after", c.opponent.give_way_after);
  o.describe("back_off", "[m] how far the opponent backs off, where its rear is free, when it gives way");
  c.opponent.back_off = nonNegative(o, "back_off", c.opponent.back_off);
  {
    int imitated = 1;  // the robot it imitates: ours
    for (const auto& kv : c.robot.collectors) imitated = std::max(imitated, kv.second.capacity);
    const Params p = o.block("player");
    p.describe("capacity", "how many elements the player carries at once (unset: our largest collector's)");
    c.opponent.player_capacity = static_cast<int>(integer(p, "capacity", imitated));
    p.requireInRange("capacity", c.opponent.player_capacity, 1, 100);
    p.describe("handling_time", "[s] how long the player takes to take or put down an element");
    c.opponent.player_handling_time = nonNegative(p, "handling_time", c.opponent.player_handling_time);
  }
  if (c.opponent.mode == "script" && c.opponent.waypoints.empty())
    fail(o, "waypoints", "mode script needs at least one waypoint");

  const Params m = w.block("match");
  m.describe("year", "the rules the match is scored by: 2008 or 2009");
  c.match.year = oneOf(m, "year", c.match.year, {"2008", "2009"});
  m.describe("duration", "[s] the match's length; unset, the brain's match timer brain/match/duration sets it");
  c.match.duration = positive(m, "duration", c.match.duration);
  m.describe("start_switch", "a manual switch under robot/switches: the match starts when it opens (empty: at t = 0)");
  c.match.start_switch = str(m, "start_switch", "");
  if (!c.match.start_switch.empty() && !c.robot.switches.count(c.match.start_switch))
    fail(m, "start_switch", "= '" + c.match.start_switch + "': must name a switch under robot/switches");
  return c;
}

}  // namespace robot_sim
