#include "hal_nodes/driver/recovery.h"

#include <cmath>
#include <cstdio>

namespace hal_nodes {
namespace driver {

namespace {
constexpr double kBackOffTolerance = 0.01;  // [m]
constexpr double kTurnTolerance = 0.05;     // [rad]
constexpr double kMinTurn = 0.05;           // [rad] a stall with less turn left was not a turn
}  // namespace

const char* RecoveryStep::name(Kind kind) {
  switch (kind) {
    case Kind::BACK_OFF: return "back_off";
    case Kind::TURN_OTHER_WAY: return "turn_other_way";
    case Kind::WAIT: return "wait";
  }
  return "?";
}

RecoveryConfig readRecoveryConfig(const robot_core::Params& driver) {
  const robot_core::Params p = driver.block("recovery");
  RecoveryConfig c;
  p.describe("rear_rangers", "names on avoidance/ranger_prefix looking backwards (back_off needs them)");
  c.rear_rangers = p.optionalStringList("rear_rangers");
  p.describe("rear_margin", "[m] kept free behind a back-off");
  c.rear_margin = p.optionalDouble("rear_margin", c.rear_margin);
  p.requireInRange("rear_margin", c.rear_margin, 0.0, 1.0);
  p.describe("behaviors", "the recoveries tried, in this order, before a blocked goal ends BLOCKED");
  for (const robot_core::Params& b : p.items("behaviors")) {
    RecoveryStep s;
    b.describe("type", "back_off (drive backwards where the rear is free), turn_other_way, or wait (stand still)");
    const std::string type = b.requireString("type");
    b.requireOneOf("type", type, {"back_off", "turn_other_way", "wait"});
    s.kind = type == "back_off" ? RecoveryStep::Kind::BACK_OFF
             : type == "turn_other_way" ? RecoveryStep::Kind::TURN_OTHER_WAY : RecoveryStep::Kind::WAIT;
    b.describe("distance", "[m] back_off: how far to drive backwards");
    s.distance = b.optionalDouble("distance", s.distance);
    b.requireInRange("distance", s.distance, 0.01, 1.0);
    b.describe("duration", "[s] wait: how long to stand still");
    s.duration = b.optionalDouble("duration", s.duration);
    b.requireInRange("duration", s.duration, 0.0, 30.0);
    b.describe("max_speed", "[m/s or rad/s] back_off, turn_other_way: speed limit; 0: the configured limit");
    s.max_speed = b.optionalDouble("max_speed", s.max_speed);
    b.requireInRange("max_speed", s.max_speed, 0.0, 10.0);
    c.steps.push_back(s);
  }
  for (const auto& s : c.steps)
    if (s.kind == RecoveryStep::Kind::BACK_OFF && c.rear_rangers.empty())
      p.check("rear_rangers", "is required by back_off: a robot that cannot see behind does not back off blind");
  return c;
}

Recovery::Recovery(const RecoveryConfig& config, const AutopilotConfig& motion)
    : config_(config), straight_(motion), rotation_(motion) {}

void Recovery::reset() {
  next_ = 0;
  running_ = false;
  tried_.clear();
}

bool Recovery::start(const BlockedAt& at, double now, std::vector<std::string>* skipped) {
  running_ = false;
  while (next_ < config_.steps.size()) {
    current_ = next_++;
    const RecoveryStep& s = config_.steps[current_];
    char why[96];
    switch (s.kind) {
      case RecoveryStep::Kind::BACK_OFF:
        if (at.rear_free < s.distance + config_.rear_margin) {
          if (at.rear_free < 0.0)
            std::snprintf(why, sizeof why, "back_off: rear unknown (no fresh rear ranger)");
          else
            std::snprintf(why, sizeof why, "back_off: rear not free (%.2f m, needs %.2f m)", at.rear_free,
                          s.distance + config_.rear_margin);
          if (skipped) skipped->push_back(why);
          continue;
        }
        straight_.start(at.odom, -s.distance, kBackOffTolerance, s.max_speed);
        break;
      case RecoveryStep::Kind::TURN_OTHER_WAY:
        if (std::abs(at.turn_left) < kMinTurn) {
          if (skipped) skipped->push_back("turn_other_way: it was not turning");
          continue;
        }
        // The same heading the other way round: the complement of what was left, opposite sign.
        rotation_.start(at.odom, at.turn_left - std::copysign(2.0 * M_PI, at.turn_left), kTurnTolerance, s.max_speed);
        break;
      case RecoveryStep::Kind::WAIT:
        until_ = now + s.duration;
        break;
    }
    running_ = true;
    tried_.push_back(RecoveryStep::name(s.kind));
    return true;
  }
  return false;
}

Twist2D Recovery::step(const Pose2D& odom, const Twist2D& current, double now, double rear_free) {
  if (!running_) return Twist2D();
  const RecoveryStep& s = config_.steps[current_];
  Twist2D cmd;
  switch (s.kind) {
    case RecoveryStep::Kind::BACK_OFF:
      // Something came into the margin behind: as far as it goes.
      if (rear_free >= 0.0 && rear_free < config_.rear_margin) {
        running_ = false;
        return Twist2D();
      }
      cmd = straight_.step(odom, current);
      running_ = !straight_.done();
      break;
    case RecoveryStep::Kind::TURN_OTHER_WAY:
      cmd = rotation_.step(odom, current);
      running_ = !rotation_.done();
      break;
    case RecoveryStep::Kind::WAIT:
      running_ = now < until_;
      break;
  }
  return running_ ? cmd : Twist2D();
}

std::string Recovery::describe() const {
  if (!running_) return "";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s (%zu of %zu)", RecoveryStep::name(config_.steps[current_].kind), current_ + 1,
                config_.steps.size());
  return buf;
}

std::string Recovery::tried() const {
  std::string out;
  for (const auto& t : tried_) out += (out.empty() ? "" : ", ") + t;
  return out;
}

}  // namespace driver
}  // namespace hal_nodes
