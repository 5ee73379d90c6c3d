// Strict reading of the world's parameters: an unknown type or an out-of-range value throws
// ConfigError naming the parameter; a missing optional value takes the documented default.
#include "robot_sim/world/config.h"

#include <xmlrpcpp/XmlRpcValue.h>

#include "robot_sim/world/footprint.h"

#include <cmath>
#include <sstream>

namespace robot_sim {
namespace {

using XmlRpc::XmlRpcValue;

// A dictionary of the parameter tree with its resolved name.
class Node {
 public:
  Node(const XmlRpcValue& v, std::string path) : v_(v), path_(std::move(path)) {
    if (v_.getType() != XmlRpcValue::TypeStruct && v_.getType() != XmlRpcValue::TypeInvalid)
      fail("", "must be a dictionary");
  }
  bool has(const std::string& k) const {
    return v_.getType() == XmlRpcValue::TypeStruct && const_cast<XmlRpcValue&>(v_).hasMember(k);
  }
  const XmlRpcValue& at(const std::string& k) const { return const_cast<XmlRpcValue&>(v_)[k]; }
  std::string name(const std::string& k) const { return k.empty() ? path_ : path_ + "/" + k; }

  [[noreturn]] void fail(const std::string& k, const std::string& what) const {
    throw ConfigError("parameter " + name(k) + ": " + what);
  }

  static bool toDouble(const XmlRpcValue& x, double& out) {
    if (x.getType() == XmlRpcValue::TypeDouble) out = static_cast<double>(const_cast<XmlRpcValue&>(x));
    else if (x.getType() == XmlRpcValue::TypeInt) out = static_cast<int>(const_cast<XmlRpcValue&>(x));
    else return false;
    return std::isfinite(out);
  }

  double num(const std::string& k, double def) const {
    if (!has(k)) return def;
    double out;
    if (!toDouble(at(k), out)) fail(k, "must be a number");
    return out;
  }
  double positive(const std::string& k, double def) const {
    const double v = num(k, def);
    if (!(v > 0.0)) fail(k, "= " + fmt(v) + ": must be > 0");
    return v;
  }
  double nonNegative(const std::string& k, double def) const {
    const double v = num(k, def);
    if (v < 0.0) fail(k, "= " + fmt(v) + ": must be >= 0");
    return v;
  }
  double inRange(const std::string& k, double def, double lo, double hi) const {
    const double v = num(k, def);
    if (v < lo || v > hi) fail(k, "= " + fmt(v) + ": must be in [" + fmt(lo) + ", " + fmt(hi) + "]");
    return v;
  }
  long integer(const std::string& k, long def) const {
    if (!has(k)) return def;
    if (at(k).getType() != XmlRpcValue::TypeInt) fail(k, "must be an integer");
    return static_cast<int>(const_cast<XmlRpcValue&>(at(k)));
  }
  bool boolean(const std::string& k, bool def) const {
    if (!has(k)) return def;
    if (at(k).getType() != XmlRpcValue::TypeBoolean) fail(k, "must be true or false");
    return static_cast<bool>(const_cast<XmlRpcValue&>(at(k)));
  }
  std::string str(const std::string& k, const std::string& def) const {
    if (!has(k)) return def;
    if (at(k).getType() != XmlRpcValue::TypeString) fail(k, "must be a string");
    return static_cast<std::string>(const_cast<XmlRpcValue&>(at(k)));
  }
  std::string oneOf(const std::string& k, const std::string& def, const std::vector<std::string>& allowed) const {
    const std::string v = str(k, def);
    for (const auto& a : allowed)
      if (a == v) return v;
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    fail(k, "= '" + v + "': allowed values: " + list);
  }
  std::vector<double> numbers(const std::string& k, std::size_t n_min, std::size_t n_max) const {
    std::vector<double> out;
    if (!has(k)) return out;
    const XmlRpcValue& a = at(k);
    if (a.getType() != XmlRpcValue::TypeArray) fail(k, "must be a list of numbers");
    for (int i = 0; i < a.size(); ++i) {
      double d;
      if (!toDouble(const_cast<XmlRpcValue&>(a)[i], d)) fail(k, "must be a list of numbers");
      out.push_back(d);
    }
    if (out.size() < n_min || out.size() > n_max)
      fail(k, "must have " + std::to_string(n_min) + (n_min == n_max ? "" : ".." + std::to_string(n_max)) +
                  " numbers");
    return out;
  }
  std::vector<std::string> strings(const std::string& k) const {
    std::vector<std::string> out;
    if (!has(k)) return out;
    const XmlRpcValue& a = at(k);
    if (a.getType() != XmlRpcValue::TypeArray) fail(k, "must be a list of strings");
    for (int i = 0; i < a.size(); ++i) {
      if (const_cast<XmlRpcValue&>(a)[i].getType() != XmlRpcValue::TypeString) fail(k, "must be a list of strings");
      out.push_back(static_cast<std::string>(const_cast<XmlRpcValue&>(a)[i]));
    }
    return out;
  }
  Node child(const std::string& k) const {
    static const XmlRpcValue empty;
    return has(k) ? Node(at(k), name(k)) : Node(empty, name(k));
  }
  // The named sub-dictionaries of a dictionary (motors, encoders, ...).
  std::vector<std::pair<std::string, Node>> entries(const std::string& k) const {
    std::vector<std::pair<std::string, Node>> out;
    if (!has(k)) return out;
    XmlRpcValue& d = const_cast<XmlRpcValue&>(at(k));
    if (d.getType() != XmlRpcValue::TypeStruct) fail(k, "must be a dictionary of named blocks");
    for (auto& e : d) out.emplace_back(e.first, Node(e.second, name(k) + "/" + e.first));
    return out;
  }
  // A list of dictionaries (zones, elements).
  std::vector<Node> items(const std::string& k) const {
    std::vector<Node> out;
    if (!has(k)) return out;
    const XmlRpcValue& a = at(k);
    if (a.getType() != XmlRpcValue::TypeArray) fail(k, "must be a list");
    for (int i = 0; i < a.size(); ++i)
      out.emplace_back(const_cast<XmlRpcValue&>(a)[i], name(k) + "[" + std::to_string(i) + "]");
    return out;
  }
  Pose2D pose(const std::string& k, Pose2D def) const {
    auto v = numbers(k, 2, 3);
    if (v.empty()) return def;
    return Pose2D{v[0], v[1], v.size() > 2 ? v[2] : 0.0};
  }

 private:
  static std::string fmt(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }
  const XmlRpcValue& v_;
  std::string path_;
};

Zone parseZone(const Node& n) {
  Zone z;
  z.name = n.str("name", "");
  auto r = n.numbers("rect", 4, 4);
  if (r.empty()) n.fail("rect", "is required: [x0, y0, x1, y1] in metres");
  z.x0 = std::min(r[0], r[2]);
  z.x1 = std::max(r[0], r[2]);
  z.y0 = std::min(r[1], r[3]);
  z.y1 = std::max(r[1], r[3]);
  z.kinds = n.strings("kinds");
  z.points = static_cast<int>(n.integer("points", 0));
  z.team = n.str("team", "placer");
  return z;
}

TableConfig parseTable(const Node& n) {
  TableConfig t;
  t.length = n.positive("length", 3.0);
  t.width = n.positive("width", 2.1);
  t.border_height = n.positive("border_height", 0.07);
  const auto& b = n.has("beacons") ? n.at("beacons") : XmlRpcValue();
  if (n.has("beacons")) {
    if (b.getType() != XmlRpcValue::TypeArray) n.fail("beacons", "must be a list of [x, y]");
    for (int i = 0; i < b.size(); ++i) {
      const XmlRpcValue& p = const_cast<XmlRpcValue&>(b)[i];
      double x, y;
      if (p.getType() != XmlRpcValue::TypeArray || p.size() != 2 || !Node::toDouble(const_cast<XmlRpcValue&>(p)[0], x) ||
          !Node::toDouble(const_cast<XmlRpcValue&>(p)[1], y))
        n.fail("beacons", "must be a list of [x, y]");
      t.beacons.push_back({x, y});
    }
  } else {
    t.beacons = {{-0.062, -0.062}, {-0.062, t.width + 0.062}, {t.length + 0.062, t.width / 2.0}};
  }
  for (const auto& z : n.items("start_zones")) t.start_zones.push_back(parseZone(z));
  for (const auto& z : n.items("score_zones")) t.score_zones.push_back(parseZone(z));
  for (std::size_t i = 0; i < t.score_zones.size(); ++i) {
    const Zone& z = t.score_zones[i];
    bool known = z.team == "placer";
    for (const Zone& s : t.start_zones) known = known || s.name == z.team;
    if (!known) {
      std::string teams = "placer";
      for (const Zone& s : t.start_zones) teams += ", " + s.name;
      n.items("score_zones")[i].fail("team", "= '" + z.team + "': allowed values: " + teams +
                                                  " (a start zone's name is that team's colour)");
    }
  }
  for (const auto& e : n.items("elements")) {
    GameElement g;
    g.kind = e.str("kind", "");
    if (g.kind.empty()) e.fail("kind", "is required (e.g. ball_red, ball_white, column)");
    g.pose = e.pose("at", Pose2D{});
    if (!e.has("at")) e.fail("at", "is required: [x, y] in metres");
    g.radius = e.positive("radius", 0.035);
    g.height = e.positive("height", 0.07);
    t.elements.push_back(g);
  }
  return t;
}

RobotConfig parseRobot(const Node& n) {
  RobotConfig r;
  r.start = n.pose("start", r.start);
  r.radius = n.positive("radius", r.radius);
  if (n.has("footprint")) {
    const XmlRpcValue& f = n.at("footprint");
    const std::string form = "must be a list of at least 3 vertices [x, y] in base_link, in order around the outline";
    if (f.getType() != XmlRpcValue::TypeArray || f.size() < 3) n.fail("footprint", form);
    for (int i = 0; i < f.size(); ++i) {
      XmlRpcValue& p = const_cast<XmlRpcValue&>(f)[i];
      double x, y;
      if (p.getType() != XmlRpcValue::TypeArray || p.size() != 2 || !Node::toDouble(p[0], x) || !Node::toDouble(p[1], y))
        n.fail("footprint", form);
      r.footprint.push_back({x, y});
    }
    try {
      Footprint check(r.footprint);
    } catch (const ConfigError& e) {
      n.fail("footprint", std::string(e.what()).substr(std::string("footprint: ").size()));
    }
  }
  r.wheel_radius = n.positive("wheel_radius", r.wheel_radius);
  r.wheel_base = n.positive("wheel_base", r.wheel_base);
  for (const auto& [name, m] : n.entries("motors")) {
    MotorConfig c;
    c.drive = m.oneOf("drive", "", {"left", "right", ""});
    c.max_speed = m.positive("max_speed", c.max_speed);
    c.time_constant = m.positive("time_constant", c.time_constant);
    c.max_accel = m.positive("max_accel", c.max_accel);
    c.stall_current = m.positive("stall_current", c.stall_current);
    c.current_limit = m.positive("current_limit", c.current_limit);
    c.no_load_current = m.nonNegative("no_load_current", c.no_load_current);
    c.inverted = m.boolean("inverted", false);
    r.motors[name] = c;
  }
  int left = 0, right = 0;
  for (const auto& [name, m] : r.motors) {
    left += m.drive == "left";
    right += m.drive == "right";
  }
  if (left != 1 || right != 1)
    n.fail("motors", "needs exactly one motor with drive: left and one with drive: right");
  for (const auto& [name, e] : n.entries("encoders")) {
    EncoderConfig c;
    c.motor = e.str("motor", "");
    if (!c.motor.empty() && !r.motors.count(c.motor)) e.fail("motor", "= '" + c.motor + "': not a motor under motors");
    if (c.motor.empty()) {
      if (!e.has("y") || !e.has("radius")) e.fail("", "needs either motor (driven wheel) or y and radius (measuring wheel)");
      c.y = e.num("y", 0.0);
      c.radius = e.positive("radius", 0.03);
    }
    c.ticks_per_rev = e.positive("ticks_per_rev", 512);
    c.sign = static_cast<int>(e.integer("sign", 1));
    if (c.sign != 1 && c.sign != -1) e.fail("sign", "allowed values: 1, -1");
    r.encoders[name] = c;
  }
  for (const auto& [name, g] : n.entries("rangers")) {
    RangerConfig c;
    c.type = g.oneOf("type", "srf02", {"srf02", "sharp"});
    const bool sharp = c.type == "sharp";
    c.mount = g.pose("mount", Pose2D{});
    c.min_range = g.nonNegative("min_range", sharp ? 0.10 : 0.03);
    c.max_range = g.positive("max_range", sharp ? 0.80 : 6.0);
    if (c.max_range <= c.min_range) g.fail("max_range", "must be > min_range");
    // SRF02: the datasheet's ~55 deg cone, the field_of_view its HCL driver reports (hcl_drivers
    // srf02_registers.h), so the localization and the avoidance measure the echo the sim makes.
    c.beam_width = g.inRange("beam_width", sharp ? 0.06 : 0.96, 0.0, 3.0);
    c.noise_std = g.nonNegative("noise_std", sharp ? 0.005 : 0.01);
    c.noise_rel = g.nonNegative("noise_rel", sharp ? 0.03 : 0.0);
    c.sees_elements = g.boolean("sees_elements", false);
    r.rangers[name] = c;
  }
  for (const auto& [name, s] : n.entries("servos")) {
    ServoConfig c;
    c.min = s.num("min", c.min);
    c.max = s.num("max", c.max);
    if (c.max <= c.min) s.fail("max", "must be > min");
    c.speed = s.positive("speed", c.speed);
    c.initial = s.inRange("initial", 0.5 * (c.min + c.max), c.min, c.max);
    r.servos[name] = c;
  }
  for (const auto& [name, s] : n.entries("steppers")) {
    StepperConfig c;
    c.min = s.integer("min", 0);
    c.max = s.integer("max", 10000);
    if (c.max <= c.min) s.fail("max", "must be > min");
    c.steps_per_second = s.positive("steps_per_second", c.steps_per_second);
    c.initial = s.integer("initial", c.min);
    if (c.initial < c.min || c.initial > c.max) s.fail("initial", "must be within [min, max]");
    r.steppers[name] = c;
  }
  for (const auto& [name, s] : n.entries("switches")) {
    SwitchConfig c;
    c.type = s.oneOf("type", "", {"bumper", "limit", "manual", "element"});
    if (c.type == "bumper") {
      c.angle = s.num("angle", 0.0);
      c.span = s.inRange("span", 1.0, 0.0, 6.3);
    } else if (c.type == "limit") {
      c.actuator = s.str("actuator", "");
      if (!r.steppers.count(c.actuator) && !r.servos.count(c.actuator))
        s.fail("actuator", "= '" + c.actuator + "': must name a stepper or servo of this robot");
      c.at = s.num("at", 0.0);
      c.direction = static_cast<int>(s.integer("direction", -1));
      if (c.direction != 1 && c.direction != -1) s.fail("direction", "allowed values: 1, -1");
    } else if (c.type == "element") {
      c.x = s.num("x", 0.0);
      c.y = s.num("y", 0.0);
      c.radius = s.positive("radius", 0.03);
    }
    c.initially_closed = s.boolean("closed", false);
    r.switches[name] = c;
  }
  for (const auto& [name, s] : n.entries("collectors")) {
    CollectorConfig c;
    c.x = s.num("x", c.x);
    c.y = s.num("y", c.y);
    c.radius = s.positive("radius", c.radius);
    c.kinds = s.strings("kinds");
    c.capacity = static_cast<int>(s.integer("capacity", c.capacity));
    c.motor = s.str("motor", "");
    c.fingers = s.strings("fingers");
    if (c.fingers.empty() == c.motor.empty())
      s.fail("motor", "give either motor (a collector) or fingers + finger_closed (a gripper)");
    if (!c.motor.empty() && !r.motors.count(c.motor)) s.fail("motor", "= '" + c.motor + "': must name a motor of this robot");
    for (const auto& f : c.fingers)
      if (!r.servos.count(f)) s.fail("fingers", "= '" + f + "': must name servos of this robot");
    if (!c.fingers.empty()) {
      c.finger_closed = s.numbers("finger_closed", c.fingers.size(), c.fingers.size());
      c.finger_tolerance = s.positive("finger_tolerance", c.finger_tolerance);
    }
    r.collectors[name] = c;
  }
  const Node sl = n.child("slip");
  r.slip.per_accel = sl.nonNegative("per_accel", r.slip.per_accel);
  r.slip.noise_std = sl.nonNegative("noise_std", r.slip.noise_std);
  r.slip.max = sl.inRange("max", r.slip.max, 0.0, 1.0);
  return r;
}

}  // namespace

WorldConfig parseWorldConfig(const XmlRpcValue& world, const std::string& world_ns, const XmlRpcValue& table,
                             const std::string& table_ns) {
  const Node w(world, world_ns);
  WorldConfig c;
  c.table = parseTable(Node(table, table_ns));
  c.dt = w.inRange("dt", c.dt, 1e-4, 0.02);
  c.robot = parseRobot(w.child("robot"));

  const Node cp = w.child("compass");
  c.compass.north_deg = cp.num("north_deg", c.compass.north_deg);
  c.compass.bias_deg = cp.num("bias_deg", c.compass.bias_deg);
  c.compass.noise_std_deg = cp.nonNegative("noise_std_deg", c.compass.noise_std_deg);

  const Node b = w.child("beacons");
  auto rx = b.numbers("receiver", 2, 2);
  if (!rx.empty()) c.beacons.receiver = {rx[0], rx[1]};
  c.beacons.height_delta = b.num("height_delta", c.beacons.height_delta);
  c.beacons.period = b.positive("period", c.beacons.period);
  c.beacons.speed_of_sound = b.positive("speed_of_sound", c.beacons.speed_of_sound);
  c.beacons.noise_std = b.nonNegative("noise_std", c.beacons.noise_std);
  c.beacons.dropout = b.inRange("dropout", c.beacons.dropout, 0.0, 1.0);
  c.beacons.outlier = b.inRange("outlier", c.beacons.outlier, 0.0, 1.0);
  c.beacons.max_delta = b.positive("max_delta", c.beacons.max_delta);

  const Node bt = w.child("battery");
  c.battery.full = bt.positive("full", c.battery.full);
  c.battery.empty = bt.positive("empty", c.battery.empty);
  c.battery.life = bt.positive("life", c.battery.life);
  c.battery.internal_resistance = bt.nonNegative("internal_resistance", c.battery.internal_resistance);
  c.battery.noise_std = bt.nonNegative("noise_std", c.battery.noise_std);

  const Node o = w.child("opponent");
  c.opponent.enabled = o.boolean("enabled", c.opponent.enabled);
  c.opponent.mode = o.oneOf("mode", c.opponent.mode, {"static", "script", "random_walk"});
  c.opponent.start = o.pose("start", Pose2D{c.table.length - 0.25, 0.25, M_PI});
  c.opponent.radius = o.positive("radius", c.opponent.radius);
  c.opponent.speed = o.positive("speed", c.opponent.speed);
  c.opponent.turn_rate = o.positive("turn_rate", c.opponent.turn_rate);
  c.opponent.pause = o.nonNegative("pause", c.opponent.pause);
  c.opponent.margin = o.nonNegative("margin", c.opponent.margin);
  if (o.has("waypoints")) {
    const XmlRpcValue& a = o.at("waypoints");
    if (a.getType() != XmlRpcValue::TypeArray) o.fail("waypoints", "must be a list of [x, y]");
    for (int i = 0; i < a.size(); ++i) {
      const XmlRpcValue& p = const_cast<XmlRpcValue&>(a)[i];
      double x, y;
      if (p.getType() != XmlRpcValue::TypeArray || p.size() != 2 || !Node::toDouble(const_cast<XmlRpcValue&>(p)[0], x) ||
          !Node::toDouble(const_cast<XmlRpcValue&>(p)[1], y))
        o.fail("waypoints", "must be a list of [x, y]");
      c.opponent.waypoints.push_back({x, y});
    }
  }
  if (c.opponent.mode == "script" && c.opponent.waypoints.empty())
    o.fail("waypoints", "mode script needs at least one waypoint");

  const Node m = w.child("match");
  c.match.year = m.oneOf("year", c.match.year, {"2008", "2009"});
  c.match.duration = m.positive("duration", c.match.duration);
  c.match.start_switch = m.str("start_switch", "");
  if (!c.match.start_switch.empty() && !c.robot.switches.count(c.match.start_switch))
    m.fail("start_switch", "= '" + c.match.start_switch + "': must name a switch under robot/switches");
  return c;
}

}  // namespace robot_sim
