#include "robot_sim/world/sim_world.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "robot_sim/world/battery_model.h"
#include "robot_sim/world/compass_model.h"
#include "robot_sim/world/diff_drive.h"
#include "robot_sim/world/ranger_model.h"
#include "robot_sim/world/world_faults.h"

namespace robot_sim {

SimWorld::SimWorld(const WorldConfig& config, unsigned seed)
    : config_(config),
      seed_(seed),
      table_(config.table.length, config.table.width),
      robot_(config.robot, seed),
      game_(config),
      opponent_(config.opponent, table_),
      beacons_(config.beacons, config.table.beacons),
      opponent_rng_(seed, "opponent"),
      beacon_rng_(seed, "beacons"),
      compass_rng_(seed, "compass"),
      battery_rng_(seed, "battery") {
  for (const auto& [name, c] : config.robot.servos) servos_[name] = ServoState{c.initial, c.initial};
  for (const auto& [name, c] : config.robot.steppers) steppers_[name] = StepperState{c.initial, c.initial, 0.0};
  for (const auto& [name, c] : config.robot.switches)
    if (c.type == "manual") manual_switches_[name] = c.initially_closed;
  for (const auto& [name, c] : config.robot.rangers) ranger_rng_.emplace(name, Rng(seed, "ranger/" + name));
  if (config.match.start_switch.empty())
    game_.begin(time_, robot_.pose(), config_.opponent.enabled ? std::optional<Pose2D>(opponent_.pose()) : std::nullopt);
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
  std::lock_guard<Mutex> lock(mutex_);
  return std::vector<std::string>(unknown_list_.begin(), unknown_list_.end());
}

int SimWorld::unknownNameCount() const {
  std::lock_guard<Mutex> lock(mutex_);
  return unknown_names_;
}

// ---------------------------------------------------------------- World: actuators
double SimWorld::time() const {
  std::lock_guard<Mutex> lock(mutex_);
  return time_;
}

void SimWorld::setMotorCommand(const std::string& motor, double fraction) {
  std::lock_guard<Mutex> lock(mutex_);
  if (!robot_.setMotorCommand(motor, fraction)) noteUnknown("motor", motor);
}

double SimWorld::motorCurrent(const std::string& motor) const {
  std::lock_guard<Mutex> lock(mutex_);
  const MotorState* m = robot_.motor(motor);
  if (!m) noteUnknown("motor", motor);
  return m ? m->current : 0.0;
}

void SimWorld::setServoTarget(const std::string& servo, double position) {
  std::lock_guard<Mutex> lock(mutex_);
  if (ServoState* s = find(servos_, servo, "servo"))
    if (std::isfinite(position)) s->target = position;
}

double SimWorld::servoPosition(const std::string& servo) const {
  std::lock_guard<Mutex> lock(mutex_);
  auto* s = find(const_cast<std::map<std::string, ServoState>&>(servos_), servo, "servo");
  return s ? s->position : 0.0;
}

void SimWorld::setStepperTarget(const std::string& stepper, int64_t steps) {
  std::lock_guard<Mutex> lock(mutex_);
  if (StepperState* s = find(steppers_, stepper, "stepper")) s->target = steps;
}

int64_t SimWorld::stepperPosition(const std::string& stepper) const {
  std::lock_guard<Mutex> lock(mutex_);
  auto* s = find(const_cast<std::map<std::string, StepperState>&>(steppers_), stepper, "stepper");
  return s ? s->position : 0;
}

// ---------------------------------------------------------------- World: sensors
int64_t SimWorld::encoderTicks(const std::string& encoder) const {
  std::lock_guard<Mutex> lock(mutex_);
  if (!robot_.hasEncoder(encoder)) {
    noteUnknown("encoder", encoder);
    return 0;
  }
  return robot_.encoderTicks(encoder);
}

double SimWorld::measureRange(const std::string& ranger) {
  std::lock_guard<Mutex> lock(mutex_);
  auto it = config_.robot.rangers.find(ranger);
  if (it == config_.robot.rangers.end()) {
    noteUnknown("ranger", ranger);
    return std::numeric_limits<double>::infinity();
  }
  const double r = robot_sim::trueRange(it->second, robot_.pose(), table_, rangerObstacles(it->second.sees_elements));
  return noisyRange(it->second, r, ranger_rng_.at(ranger));
}

double SimWorld::trueRange(const std::string& ranger) const {
  std::lock_guard<Mutex> lock(mutex_);
  auto it = config_.robot.rangers.find(ranger);
  if (it == config_.robot.rangers.end()) return std::numeric_limits<double>::infinity();
  return robot_sim::trueRange(it->second, robot_.pose(), table_, rangerObstacles(it->second.sees_elements));
}

double SimWorld::measureCompassDeg() {
  std::lock_guard<Mutex> lock(mutex_);
  return noisyCompassDeg(config_.compass, robot_.pose().theta, compass_rng_);
}

bool SimWorld::switchClosed(const std::string& name) const {
  std::lock_guard<Mutex> lock(mutex_);
  auto it = config_.robot.switches.find(name);
  if (it == config_.robot.switches.end()) {
    noteUnknown("switch", name);
    return false;
  }
  const SwitchConfig& s = it->second;
  if (s.type == "manual") return manual_switches_.at(name);
  if (s.type == "bumper") return robot_.bumperClosed(s);
  if (s.type == "limit") {
    double pos;
    auto st = steppers_.find(s.actuator);
    if (st != steppers_.end()) pos = static_cast<double>(st->second.position);
    else pos = servos_.at(s.actuator).position;
    return s.direction < 0 ? pos <= s.at : pos >= s.at;
  }
  // element: something under the sensor, on the table or held there (a column in the hand)
  const Pose2D p = robot_.toMap(s.x, s.y);
  for (const auto& e : game_.elements())
    if (std::hypot(e.pose.x - p.x, e.pose.y - p.y) <= s.radius) return true;
  return false;
}

double SimWorld::batteryVoltage() const {
  std::lock_guard<Mutex> lock(mutex_);
  double current = 0.0;
  for (const auto& kv : config_.robot.motors) current += std::abs(robot_.motor(kv.first)->current);
  return robot_sim::batteryVoltage(config_.battery, time_, current, battery_rng_);
}

std::vector<BeaconMeasurement> SimWorld::takeBeaconMeasurements() {
  std::lock_guard<Mutex> lock(mutex_);
  return beacons_.take();
}

WorldSnapshot SimWorld::snapshot() const {
  std::lock_guard<Mutex> lock(mutex_);
  WorldSnapshot s;
  s.time = time_;
  s.robot = robot_.pose();
  s.robot_radius = robot_.footprint().boundingRadius();
  s.opponent = opponent_.pose();
  s.opponent_radius = config_.opponent.enabled ? opponent_.radius() : 0.0;
  s.elements = game_.elements();
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
std::vector<Circle> SimWorld::rangerObstacles(bool with_elements) const {
  std::vector<Circle> out;
  if (config_.opponent.enabled) out.push_back(opponent_.outline());
  if (with_elements)
    for (const auto& e : game_.elements())
      if (!e.carried) out.push_back(Circle{e.pose.x, e.pose.y, e.radius});
  return out;
}

Obstacles SimWorld::obstacles() const {
  Obstacles o;
  o.table_length = config_.table.length;
  o.table_width = config_.table.width;
  if (config_.opponent.enabled) o.circles.push_back(opponent_.outline());
  return o;
}

void SimWorld::step() {
  std::lock_guard<Mutex> lock(mutex_);
  const double dt = config_.dt;
  ++steps_;
  time_ = static_cast<double>(steps_) * dt;  // no drift from summing dt
  applyScheduled();
  for (auto& kv : servos_) stepServo(config_.robot.servos.at(kv.first), kv.second, dt);
  for (auto& kv : steppers_) stepStepper(config_.robot.steppers.at(kv.first), kv.second, dt);
  robot_.step(dt, obstacles());
  if (config_.opponent.enabled) opponent_.step(dt, robot_.placed(), opponent_rng_, game_);
  game_.stepElements(dt, robot_, servos_,
                     config_.opponent.enabled ? std::optional<Circle>(opponent_.outline()) : std::nullopt);
  beacons_.step(time_, robot_.pose(), beacon_rng_);
  stepMatch();
}

void SimWorld::applyScheduled() {
  while (!scheduled_.empty() && scheduled_.front().first <= time_ + 1e-9) {
    robot_.setMotorCommand(scheduled_.front().second.first, std::clamp(scheduled_.front().second.second, -1.0, 1.0));
    scheduled_.pop_front();
  }
}

void SimWorld::stepMatch() {
  if (!game_.started()) {
    // The start cord: the match starts when the switch opens.
    if (!manual_switches_.at(config_.match.start_switch))
      game_.begin(time_, robot_.pose(),
                  config_.opponent.enabled ? std::optional<Pose2D>(opponent_.pose()) : std::nullopt);
    return;
  }
  game_.referee(time_);
}

bool SimWorld::startMatch() {
  std::lock_guard<Mutex> lock(mutex_);
  if (game_.started()) return false;
  bool& cord_closed = manual_switches_.at(config_.match.start_switch);
  if (!cord_closed) return false;  // pulled already: the match starts at this step
  cord_closed = false;             // as the cord is pulled
  return true;
}

// ---------------------------------------------------------------- controls and truth
void SimWorld::scheduleMotorCommand(double at, const std::string& motor, double fraction) {
  std::lock_guard<Mutex> lock(mutex_);
  if (!robot_.hasMotor(motor)) {
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
  std::lock_guard<Mutex> lock(mutex_);
  robot_.teleport(pose);
}

void SimWorld::placeOpponent(const Pose2D& pose, bool hold) {
  std::lock_guard<Mutex> lock(mutex_);
  opponent_.place(pose, hold);
}

bool SimWorld::setSwitch(const std::string& name, bool closed) {
  std::lock_guard<Mutex> lock(mutex_);
  auto it = manual_switches_.find(name);
  if (it == manual_switches_.end()) return false;
  it->second = closed;
  return true;
}

bool SimWorld::isWorldFault(const std::string& kind) { return robot_sim::isWorldFault(kind); }

bool SimWorld::applyFault(const std::string& kind, const std::string& target, bool active, double magnitude,
                          std::string* why) {
  std::lock_guard<Mutex> lock(mutex_);
  return applyWorldFault(kind, target, active, magnitude,
                         WorldFaultTargets{beacons_, robot_, opponent_, config_.opponent.enabled, config_.table}, why);
}

BodyTruth SimWorld::robotTruth() const {
  std::lock_guard<Mutex> lock(mutex_);
  return BodyTruth{robot_.pose(), robot_.v(), robot_.w()};
}

BodyTruth SimWorld::opponentTruth() const {
  std::lock_guard<Mutex> lock(mutex_);
  return BodyTruth{opponent_.pose(), opponent_.v(), opponent_.w()};
}

MatchProgress SimWorld::match() const {
  std::lock_guard<Mutex> lock(mutex_);
  return game_.progress(time_);
}

std::size_t SimWorld::scoreEventCount() const {
  std::lock_guard<Mutex> lock(mutex_);
  return game_.events().size();
}

std::vector<RefereeEvent> SimWorld::scoreEvents() const {
  std::lock_guard<Mutex> lock(mutex_);
  return game_.events();
}

std::vector<GameElement> SimWorld::elements() const {
  std::lock_guard<Mutex> lock(mutex_);
  return game_.elements();
}

}  // namespace robot_sim
