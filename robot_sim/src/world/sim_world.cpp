#include "robot_sim/world/sim_world.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "robot_sim/world/battery_model.h"
#include "robot_sim/world/compass_model.h"
#include "robot_sim/world/diff_drive.h"
#include "robot_sim/world/ranger_model.h"

namespace robot_sim {

namespace {
constexpr double kContactMargin = 0.003;  // [m] a bumper closes within this of an obstacle
constexpr double kTwoPi = 2.0 * M_PI;
}  // namespace

SimWorld::SimWorld(const WorldConfig& config, unsigned seed)
    : config_(config),
      seed_(seed),
      table_(config.table.length, config.table.width),
      footprint_(robotFootprint(config.robot)),
      pose_(config.robot.start),
      elements_(config.table.elements),
      opponent_(config.opponent, table_),
      beacons_(config.beacons, config.table.beacons),
      slip_rng_(seed, "slip"),
      opponent_rng_(seed, "opponent"),
      beacon_rng_(seed, "beacons"),
      compass_rng_(seed, "compass"),
      battery_rng_(seed, "battery") {
  for (const auto& [name, c] : config.robot.motors) {
    Motor& m = motors_[name];
    m.config = c;
    if (c.drive == "left") left_ = &m;
    if (c.drive == "right") right_ = &m;
  }
  for (const auto& [name, c] : config.robot.encoders) encoders_[name].config = c;
  for (const auto& [name, c] : config.robot.servos) servos_[name] = ServoState{c.initial, c.initial};
  for (const auto& [name, c] : config.robot.steppers) steppers_[name] = StepperState{c.initial, c.initial, 0.0};
  for (const auto& [name, c] : config.robot.switches)
    if (c.type == "manual") manual_switches_[name] = c.initially_closed;
  for (const auto& [name, c] : config.robot.collectors) collectors_[name].config = c;
  for (const auto& [name, c] : config.robot.rangers) ranger_rng_.emplace(name, Rng(seed, "ranger/" + name));
  if (!left_ || !right_) throw ConfigError("the robot needs a left and a right drive motor");
  scoring_.assign(elements_.size(), Scoring{});
  if (config.match.start_switch.empty()) beginMatch();
}

template <class M>
typename M::mapped_type* SimWorld::find(M& m, const std::string& name, const char* kind) const {
  auto it = m.find(name);
  if (it == m.end()) {
    noteUnknown(kind, name);
    return nullptr;
  }
  return &it->second;
}

void SimWorld::noteUnknown(const char* kind, const std::string& name) const {
  if (name.empty()) return;  // "" is how an emulator config says "not connected"
  ++unknown_names_;
  if (unknown_list_.size() < 32) unknown_list_.insert(std::string(kind) + " '" + name + "'");
}

std::vector<std::string> SimWorld::unknownNames() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::vector<std::string>(unknown_list_.begin(), unknown_list_.end());
}

int SimWorld::unknownNameCount() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return unknown_names_;
}

// ---------------------------------------------------------------- World: actuators
double SimWorld::time() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return time_;
}

void SimWorld::setMotorCommand(const std::string& motor, double fraction) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (Motor* m = find(motors_, motor, "motor")) m->state.command = std::isfinite(fraction) ? std::clamp(fraction, -1.0, 1.0) : 0.0;
}

double SimWorld::motorCurrent(const std::string& motor) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto* m = find(const_cast<std::map<std::string, Motor>&>(motors_), motor, "motor");
  return m ? m->state.current : 0.0;
}

void SimWorld::setServoTarget(const std::string& servo, double position) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (ServoState* s = find(servos_, servo, "servo"))
    if (std::isfinite(position)) s->target = position;
}

double SimWorld::servoPosition(const std::string& servo) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto* s = find(const_cast<std::map<std::string, ServoState>&>(servos_), servo, "servo");
  return s ? s->position : 0.0;
}

void SimWorld::setStepperTarget(const std::string& stepper, int64_t steps) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (StepperState* s = find(steppers_, stepper, "stepper")) s->target = steps;
}

int64_t SimWorld::stepperPosition(const std::string& stepper) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto* s = find(const_cast<std::map<std::string, StepperState>&>(steppers_), stepper, "stepper");
  return s ? s->position : 0;
}

// ---------------------------------------------------------------- World: sensors
int64_t SimWorld::encoderTicks(const std::string& encoder) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto* e = find(const_cast<std::map<std::string, Encoder>&>(encoders_), encoder, "encoder");
  if (!e) return 0;
  return static_cast<int64_t>(std::floor(e->turns * e->config.ticks_per_rev)) * e->config.sign;
}

double SimWorld::measureRange(const std::string& ranger) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = config_.robot.rangers.find(ranger);
  if (it == config_.robot.rangers.end()) {
    noteUnknown("ranger", ranger);
    return std::numeric_limits<double>::infinity();
  }
  const double r = robot_sim::trueRange(it->second, pose_, table_, obstacles(it->second.sees_elements));
  return noisyRange(it->second, r, ranger_rng_.at(ranger));
}

double SimWorld::trueRange(const std::string& ranger) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = config_.robot.rangers.find(ranger);
  if (it == config_.robot.rangers.end()) return std::numeric_limits<double>::infinity();
  return robot_sim::trueRange(it->second, pose_, table_, obstacles(it->second.sees_elements));
}

double SimWorld::measureCompassDeg() {
  std::lock_guard<std::mutex> lock(mutex_);
  return noisyCompassDeg(config_.compass, pose_.theta, compass_rng_);
}

bool SimWorld::switchClosed(const std::string& name) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = config_.robot.switches.find(name);
  if (it == config_.robot.switches.end()) {
    noteUnknown("switch", name);
    return false;
  }
  const SwitchConfig& s = it->second;
  if (s.type == "manual") return manual_switches_.at(name);
  if (s.type == "bumper") {
    if (!contact_) return false;
    const double rel = wrapAngle(contact_angle_ - s.angle);
    return std::abs(rel) <= 0.5 * s.span;
  }
  if (s.type == "limit") {
    double pos;
    auto st = steppers_.find(s.actuator);
    if (st != steppers_.end()) pos = static_cast<double>(st->second.position);
    else pos = servos_.at(s.actuator).position;
    return s.direction < 0 ? pos <= s.at : pos >= s.at;
  }
  // element: something under the sensor
  const Pose2D p = toMap(s.x, s.y);
  for (const auto& e : elements_)
    if (!e.carried && std::hypot(e.pose.x - p.x, e.pose.y - p.y) <= s.radius) return true;
  return false;
}

double SimWorld::batteryVoltage() const {
  std::lock_guard<std::mutex> lock(mutex_);
  double current = 0.0;
  for (const auto& kv : motors_) current += std::abs(kv.second.state.current);
  return robot_sim::batteryVoltage(config_.battery, time_, current, battery_rng_);
}

std::vector<BeaconMeasurement> SimWorld::takeBeaconMeasurements() {
  std::lock_guard<std::mutex> lock(mutex_);
  return beacons_.take();
}

WorldSnapshot SimWorld::snapshot() const {
  std::lock_guard<std::mutex> lock(mutex_);
  WorldSnapshot s;
  s.time = time_;
  s.robot = pose_;
  s.robot_radius = footprint_.boundingRadius();
  s.opponent = opponent_.pose();
  s.opponent_radius = config_.opponent.enabled ? opponent_.radius() : 0.0;
  s.elements = elements_;
  s.table_length = config_.table.length;
  s.table_width = config_.table.width;
  return s;
}

bool SimWorld::has(const std::string& kind, const std::string& name) const {
  const auto& r = config_.robot;
  if (kind == "motor") return r.motors.count(name) > 0;
  if (kind == "encoder") return r.encoders.count(name) > 0;
  if (kind == "ranger") return r.rangers.count(name) > 0;
  if (kind == "switch") return r.switches.count(name) > 0;
  if (kind == "servo") return r.servos.count(name) > 0;
  if (kind == "stepper") return r.steppers.count(name) > 0;
  return false;
}

// ---------------------------------------------------------------- stepping
std::vector<Circle> SimWorld::obstacles(bool with_elements) const {
  std::vector<Circle> out;
  if (config_.opponent.enabled) out.push_back(opponent_.outline());
  if (with_elements)
    for (const auto& e : elements_)
      if (!e.carried) out.push_back(Circle{e.pose.x, e.pose.y, e.radius});
  return out;
}

Pose2D SimWorld::toMap(double x, double y) const {
  const double c = std::cos(pose_.theta), s = std::sin(pose_.theta);
  return Pose2D{pose_.x + c * x - s * y, pose_.y + s * x + c * y, pose_.theta};
}

void SimWorld::step() {
  std::lock_guard<std::mutex> lock(mutex_);
  const double dt = config_.dt;
  ++steps_;
  time_ = static_cast<double>(steps_) * dt;  // no drift from summing dt
  applyScheduled();
  for (auto& kv : servos_) stepServo(config_.robot.servos.at(kv.first), kv.second, dt);
  for (auto& kv : steppers_) stepStepper(config_.robot.steppers.at(kv.first), kv.second, dt);
  stepRobot(dt);
  const std::vector<Point2D> ours = footprint_.placed(pose_);  // our outline after this step
  if (config_.opponent.enabled) {
    opponent_.step(dt, ours, opponent_rng_);
  }
  stepElements(dt, ours);
  beacons_.step(time_, pose_, beacon_rng_);
  stepMatch();
}

void SimWorld::applyScheduled() {
  while (!scheduled_.empty() && scheduled_.front().first <= time_ + 1e-9) {
    auto it = motors_.find(scheduled_.front().second.first);
    if (it != motors_.end()) it->second.state.command = std::clamp(scheduled_.front().second.second, -1.0, 1.0);
    scheduled_.pop_front();
  }
}

void SimWorld::stepRobot(double dt) {
  const RobotConfig& rc = config_.robot;
  for (auto& kv : motors_) stepMotor(kv.second.config, kv.second.state, dt);
  // Each drive wheel's contact moves at its surface speed reduced by the slip.
  for (Motor* m : {left_, right_}) {
    const double surface = m->state.speed * rc.wheel_radius;
    const double accel = m->state.accel * rc.wheel_radius;
    const double slip = slipFraction(rc.slip, surface, accel, m->extra_slip, slip_rng_);
    m->ground_speed = surface * (1.0 - slip);
  }
  double v, w;
  wheelsToTwist(left_->ground_speed, right_->ground_speed, rc.wheel_base, v, w);
  Pose2D next = integrateTwist(pose_, v, w, dt);

  // Collisions of the outline: a move that pushes further into a border or the opponent does
  // not happen; the drive wheels stall (the robot stops) and the bumper at the contact closes.
  const std::vector<Point2D> outline_now = footprint_.placed(pose_), outline_next = footprint_.placed(next);
  const double border_now = borderContact(outline_now, table_.length(), table_.width()).clearance;
  const double border_next = borderContact(outline_next, table_.length(), table_.width()).clearance;
  double opp_now = std::numeric_limits<double>::infinity(), opp_next = opp_now;
  if (config_.opponent.enabled) {
    opp_now = circleContact(outline_now, opponent_.outline()).clearance;
    opp_next = circleContact(outline_next, opponent_.outline()).clearance;
  }
  const bool blocked = (border_next < 0.0 && border_next < border_now - 1e-12) ||
                       (opp_next < 0.0 && opp_next < opp_now - 1e-12);
  if (blocked) {
    for (Motor* m : {left_, right_}) {
      stepMotor(m->config, m->state, dt, true);
      m->ground_speed = 0.0;
    }
    v = w = 0.0;
    next = pose_;
  }
  // Encoders: driven ones count their wheel's turning (slip included), measuring wheels the
  // ground under them.
  for (auto& kv : encoders_) {
    Encoder& e = kv.second;
    if (e.config.driven()) {
      e.turns += motors_.at(e.config.motor).state.speed * dt / kTwoPi;
    } else {
      e.turns += (v - w * e.config.y) * dt / (kTwoPi * e.config.radius);
    }
  }
  pose_ = next;
  v_ = v;
  w_ = w;
  // Contact for the bumpers: the nearest obstacle within the margin, located on the outline.
  const std::vector<Point2D> outline = blocked ? outline_now : outline_next;
  Contact touch = borderContact(outline, table_.length(), table_.width());
  if (config_.opponent.enabled) {
    const Contact o = circleContact(outline, opponent_.outline());
    if (o.clearance < touch.clearance) touch = o;
  }
  contact_ = touch.clearance <= kContactMargin;
  if (contact_)
    contact_angle_ = wrapAngle(std::atan2(touch.point.y - pose_.y, touch.point.x - pose_.x) - pose_.theta);
}

// A gripper (the 2009 hand) takes the nearest matching element at its mouth when its fingers
// close, carries it, and puts it down at the mouth when a finger opens. The lift's height is
// not modelled: a released element stands on the table (no stacking).
void SimWorld::stepGripper(Collector& c) {
  bool closed = true;
  for (std::size_t i = 0; i < c.config.fingers.size(); ++i)
    closed = closed && std::abs(servos_.at(c.config.fingers[i]).position - c.config.finger_closed[i]) <= c.config.finger_tolerance;
  const Pose2D mouth = toMap(c.config.x, c.config.y);
  if (!closed) {
    for (GameElement* e : c.gripped) {
      e->carried = false;
      e->moved_by = Mover::ours;
      e->pose.x = mouth.x;
      e->pose.y = mouth.y;
    }
    c.gripped.clear();
    c.held = 0;
    c.was_closed = false;
    return;
  }
  if (c.was_closed) return;  // fingers closed on nothing stay empty until they open again
  c.was_closed = true;
  GameElement* best = nullptr;
  double best_d = c.config.radius;
  for (auto& e : elements_) {
    const bool kind_ok =
        c.config.kinds.empty() || std::find(c.config.kinds.begin(), c.config.kinds.end(), e.kind) != c.config.kinds.end();
    const double d = std::hypot(e.pose.x - mouth.x, e.pose.y - mouth.y);
    if (!e.carried && kind_ok && d <= best_d) {
      best = &e;
      best_d = d;
    }
  }
  if (best && c.held < c.config.capacity) {
    best->carried = true;
    best->moved_by = Mover::ours;
    c.gripped.push_back(best);
    ++c.held;
  }
}

void SimWorld::stepElements(double dt, const std::vector<Point2D>& ours) {
  // Collectors swallow matching elements at their mouth while their motor runs forward and
  // spit one out ahead every 0.25 s while it runs backward.
  for (auto& kv : collectors_) {
    Collector& c = kv.second;
    if (!c.config.fingers.empty()) {
      stepGripper(c);
      continue;
    }
    const double cmd = motors_.at(c.config.motor).state.command;
    const Pose2D mouth = toMap(c.config.x, c.config.y);
    c.eject_cooldown = std::max(0.0, c.eject_cooldown - dt);
    for (auto& e : elements_) {
      const bool kind_ok =
          c.config.kinds.empty() || std::find(c.config.kinds.begin(), c.config.kinds.end(), e.kind) != c.config.kinds.end();
      if (cmd > 0.1 && !e.carried && kind_ok && c.held < c.config.capacity &&
          std::hypot(e.pose.x - mouth.x, e.pose.y - mouth.y) <= c.config.radius) {
        e.carried = true;
        e.moved_by = Mover::ours;
        ++c.held;
      } else if (cmd < -0.1 && e.carried && c.held > 0 && c.eject_cooldown <= 0.0 && kind_ok) {
        e.carried = false;
        e.moved_by = Mover::ours;
        e.pose = toMap(c.config.x + c.config.radius + e.radius, c.config.y);
        --c.held;
        c.eject_cooldown = 0.25;
      }
    }
  }
  // Carried elements ride along; loose ones are pushed out of our outline (along its normal at
  // the contact) and of the opponent's circle, and stay on the table.
  const double reach = footprint_.boundingRadius();
  for (auto& e : elements_) {
    if (e.carried) {
      e.pose.x = pose_.x;
      e.pose.y = pose_.y;
      continue;
    }
    if (std::hypot(e.pose.x - pose_.x, e.pose.y - pose_.y) < reach + e.radius) {
      Circle c{e.pose.x, e.pose.y, e.radius};
      if (pushOut(ours, c)) {
        e.pose.x = c.x;
        e.pose.y = c.y;
        e.moved_by = Mover::ours;
      }
    }
    if (config_.opponent.enabled) {
      const Circle pusher = opponent_.outline();
      const double dx = e.pose.x - pusher.x, dy = e.pose.y - pusher.y;
      const double d = std::hypot(dx, dy);
      const double need = pusher.r + e.radius;
      if (d < need) {
        const double ux = d > 1e-9 ? dx / d : 1.0, uy = d > 1e-9 ? dy / d : 0.0;
        e.pose.x = pusher.x + ux * need;
        e.pose.y = pusher.y + uy * need;
        e.moved_by = Mover::opponent;
      }
    }
    e.pose.x = std::clamp(e.pose.x, e.radius, config_.table.length - e.radius);
    e.pose.y = std::clamp(e.pose.y, e.radius, config_.table.width - e.radius);
  }
}

// A zone with a team colour scores for the team of that colour; a "placer" zone for the robot
// that last moved the element (nobody's points for an element nobody touched).
Mover SimWorld::zoneTeam(const Zone& zone, const GameElement& e) const {
  if (zone.team.empty() || zone.team == "placer") return e.moved_by;
  if (zone.team == colour_ours_) return Mover::ours;
  if (zone.team == colour_opponent_) return Mover::opponent;
  return Mover::nobody;
}

void SimWorld::updateScoring() {
  const double t = time_ - match_start_;
  for (std::size_t i = 0; i < elements_.size(); ++i) {
    const GameElement& e = elements_[i];
    Scoring now;
    if (!e.carried) {
      for (std::size_t z = 0; z < config_.table.score_zones.size(); ++z) {
        const Zone& zone = config_.table.score_zones[z];
        const bool kind_ok = zone.kinds.empty() || std::find(zone.kinds.begin(), zone.kinds.end(), e.kind) != zone.kinds.end();
        if (kind_ok && zone.contains(e.pose.x, e.pose.y)) {
          now.zone = static_cast<int>(z);
          now.team = zoneTeam(zone, e);
          break;
        }
      }
      if (now.team == Mover::nobody) now.zone = -1;  // lies there for nobody: no points, no event
    }
    Scoring& was = scoring_[i];
    if (now.zone == was.zone && now.team == was.team) continue;
    const std::string name = e.kind + "#" + std::to_string(i);
    if (was.zone >= 0) {
      const Zone& z = config_.table.score_zones[was.zone];
      score_events_.push_back(RefereeEvent{t, name, z.name, -z.points, was.team});
    }
    if (now.zone >= 0) {
      const Zone& z = config_.table.score_zones[now.zone];
      score_events_.push_back(RefereeEvent{t, name, z.name, z.points, now.team});
    }
    was = now;
  }
}

// Our colour is the start zone our robot stands in when the match starts; the opponent's the
// start zone it stands in, else another start zone.
void SimWorld::beginMatch() {
  match_started_ = true;
  match_start_ = time_;
  scoring_.assign(elements_.size(), Scoring{});
  const Pose2D opp = opponent_.pose();
  for (const Zone& z : config_.table.start_zones) {
    if (colour_ours_.empty() && z.contains(pose_.x, pose_.y)) colour_ours_ = z.name;
  }
  for (const Zone& z : config_.table.start_zones) {
    if (z.name != colour_ours_ && config_.opponent.enabled && z.contains(opp.x, opp.y)) colour_opponent_ = z.name;
  }
  for (const Zone& z : config_.table.start_zones) {
    if (colour_opponent_.empty() && z.name != colour_ours_) colour_opponent_ = z.name;
  }
}

void SimWorld::stepMatch() {
  if (!match_started_) {
    // The start cord: the match starts when the switch opens.
    if (!manual_switches_.at(config_.match.start_switch)) beginMatch();
    return;
  }
  if (match_over_) return;
  updateScoring();
  if (time_ - match_start_ >= config_.match.duration) match_over_ = true;  // the score freezes
}

bool SimWorld::startMatch() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (match_started_) return false;
  bool& cord_closed = manual_switches_.at(config_.match.start_switch);
  if (!cord_closed) return false;  // pulled already: the match starts at this step
  cord_closed = false;             // as the cord is pulled
  return true;
}

// ---------------------------------------------------------------- controls and truth
void SimWorld::scheduleMotorCommand(double at, const std::string& motor, double fraction) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!motors_.count(motor)) {
    noteUnknown("motor", motor);
    return;
  }
  const auto entry = std::make_pair(at, std::make_pair(motor, std::isfinite(fraction) ? fraction : 0.0));
  // Keep the queue sorted by time, stable for equal times (the order they were given).
  auto pos = std::upper_bound(scheduled_.begin(), scheduled_.end(), at,
                              [](double t, const auto& item) { return t < item.first; });
  scheduled_.insert(pos, entry);
}

void SimWorld::teleport(const Pose2D& pose) {
  std::lock_guard<std::mutex> lock(mutex_);
  pose_ = pose;
  pose_.theta = wrapAngle(pose.theta);
  v_ = w_ = 0.0;
  for (auto& kv : motors_) kv.second.state.speed = 0.0;
}

void SimWorld::placeOpponent(const Pose2D& pose, bool hold) {
  std::lock_guard<std::mutex> lock(mutex_);
  opponent_.place(pose, hold);
}

bool SimWorld::setSwitch(const std::string& name, bool closed) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = manual_switches_.find(name);
  if (it == manual_switches_.end()) return false;
  it->second = closed;
  return true;
}

bool SimWorld::isWorldFault(const std::string& kind) {
  return kind == "beacon_silent" || kind == "wheel_slip" || kind == "opponent_blocks";
}

bool SimWorld::applyFault(const std::string& kind, const std::string& target, bool active, double magnitude,
                          std::string* why) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (kind == "beacon_silent") {
    char* end = nullptr;
    const long id = std::strtol(target.c_str(), &end, 10);
    if (target.empty() || *end || id < 0 || id >= static_cast<long>(beacons_.count())) {
      if (why) *why = "beacon_silent: target must be a beacon id 0.." + std::to_string(beacons_.count() - 1);
      return false;
    }
    beacons_.setSilent(static_cast<int>(id), active);
    return true;
  }
  if (kind == "wheel_slip") {
    auto it = motors_.find(target);
    if (it == motors_.end() || it->second.config.drive.empty()) {
      if (why) *why = "wheel_slip: target must be a drive motor (" + config_.robot.motors.begin()->first + ", ...)";
      return false;
    }
    it->second.extra_slip = active ? (magnitude > 0.0 ? std::min(magnitude, 1.0) : 0.6) : 0.0;
    return true;
  }
  if (kind == "opponent_blocks") {
    if (!config_.opponent.enabled) {
      if (why) *why = "opponent_blocks: the opponent is disabled (sim/world/opponent/enabled)";
      return false;
    }
    if (active) {
      // The opponent steps into our path, facing us, and stays there until the fault ends.
      const double gap = magnitude > 0.0 ? magnitude : 0.1;
      const double d = footprint_.reach(0.0) + opponent_.radius() + gap;
      Pose2D p{pose_.x + d * std::cos(pose_.theta), pose_.y + d * std::sin(pose_.theta),
               wrapAngle(pose_.theta + M_PI)};
      const double r = opponent_.radius();
      p.x = std::clamp(p.x, r, config_.table.length - r);
      p.y = std::clamp(p.y, r, config_.table.width - r);
      opponent_.place(p, true);
    } else {
      opponent_.place(opponent_.pose(), false);
    }
    return true;
  }
  if (why) *why = "not a world fault: " + kind;
  return false;
}

BodyTruth SimWorld::robotTruth() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return BodyTruth{pose_, v_, w_};
}

BodyTruth SimWorld::opponentTruth() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return BodyTruth{opponent_.pose(), opponent_.v(), opponent_.w()};
}

MatchProgress SimWorld::match() const {
  std::lock_guard<std::mutex> lock(mutex_);
  MatchProgress m;
  m.started = match_started_;
  m.elapsed = match_started_ ? std::min(time_ - match_start_, config_.match.duration) : 0.0;
  m.remaining = config_.match.duration - m.elapsed;
  m.over = match_over_;
  for (const Scoring& s : scoring_) {
    if (s.zone < 0) continue;
    const int points = config_.table.score_zones[s.zone].points;
    if (s.team == Mover::ours) m.score_ours += points;
    if (s.team == Mover::opponent) m.score_opponent += points;
  }
  m.colour_ours = colour_ours_;
  m.colour_opponent = colour_opponent_;
  return m;
}

std::size_t SimWorld::scoreEventCount() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return score_events_.size();
}

std::vector<RefereeEvent> SimWorld::scoreEvents() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return score_events_;
}

std::vector<GameElement> SimWorld::elements() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return elements_;
}

}  // namespace robot_sim
