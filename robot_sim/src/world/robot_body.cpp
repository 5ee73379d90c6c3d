#include "robot_sim/world/robot_body.h"

#include <algorithm>
#include <cmath>

#include "robot_sim/world/diff_drive.h"

namespace robot_sim {

namespace {
constexpr double kContactMargin = 0.003;  // [m] a bumper closes within this of an obstacle
constexpr double kTwoPi = 2.0 * M_PI;
}  // namespace

RobotBody::RobotBody(const RobotConfig& config, unsigned seed)
    : config_(config), footprint_(robotFootprint(config)), pose_(config.start), slip_rng_(seed, "slip") {
  for (const auto& [name, c] : config.motors) {
    Motor& m = motors_[name];
    m.config = c;
    if (c.drive == "left") left_ = &m;
    if (c.drive == "right") right_ = &m;
  }
  for (const auto& [name, c] : config.encoders) encoders_[name].config = c;
  if (!left_ || !right_) throw ConfigError("the robot needs a left and a right drive motor");
}

Pose2D RobotBody::toMap(double x, double y) const {
  const double c = std::cos(pose_.theta), s = std::sin(pose_.theta);
  return Pose2D{pose_.x + c * x - s * y, pose_.y + s * x + c * y, pose_.theta};
}

bool RobotBody::setMotorCommand(const std::string& name, double fraction) {
  auto it = motors_.find(name);
  if (it == motors_.end()) return false;
  it->second.state.command = std::isfinite(fraction) ? std::clamp(fraction, -1.0, 1.0) : 0.0;
  return true;
}

const MotorState* RobotBody::motor(const std::string& name) const {
  auto it = motors_.find(name);
  return it == motors_.end() ? nullptr : &it->second.state;
}

bool RobotBody::setExtraSlip(const std::string& name, double fraction) {
  auto it = motors_.find(name);
  if (it == motors_.end() || it->second.config.drive.empty()) return false;
  it->second.extra_slip = fraction;
  return true;
}

int64_t RobotBody::encoderTicks(const std::string& name) const {
  auto it = encoders_.find(name);
  if (it == encoders_.end()) return 0;
  const Encoder& e = it->second;
  return static_cast<int64_t>(std::floor(e.turns * e.config.ticks_per_rev)) * e.config.sign;
}

bool RobotBody::bumperClosed(const SwitchConfig& s) const {
  if (!contact_) return false;
  return std::abs(wrapAngle(contact_angle_ - s.angle)) <= 0.5 * s.span;
}

void RobotBody::teleport(const Pose2D& pose) {
  pose_ = pose;
  pose_.theta = wrapAngle(pose.theta);
  v_ = w_ = 0.0;
  for (auto& kv : motors_) kv.second.state.speed = 0.0;
}

void RobotBody::step(double dt, const Obstacles& obstacles) {
  for (auto& kv : motors_) stepMotor(kv.second.config, kv.second.state, dt);
  // Each drive wheel's contact moves at its surface speed reduced by the slip.
  for (Motor* m : {left_, right_}) {
    const double surface = m->state.speed * config_.wheel_radius;
    const double accel = m->state.accel * config_.wheel_radius;
    const double slip = slipFraction(config_.slip, surface, accel, m->extra_slip, slip_rng_);
    m->ground_speed = surface * (1.0 - slip);
  }
  double v, w;
  wheelsToTwist(left_->ground_speed, right_->ground_speed, config_.wheel_base, v, w);
  const Pose2D wanted = integrateTwist(pose_, v, w, dt);

  // Only what goes into an obstacle is cancelled; a wheel whose travel is mostly cancelled stalls.
  const ResolvedMotion moved = resolveMotion(footprint_, pose_, wanted, obstacles, config_.wheel_base);
  if (moved.left_stalled) stepMotor(left_->config, left_->state, dt, true);
  if (moved.right_stalled) stepMotor(right_->config, right_->state, dt, true);
  if (moved.cancelled) {
    // The motion as it happened: forward along the mean heading (a slide along a wall has a
    // sideways part too, which no wheel measures), and the turn.
    const double dtheta = wrapAngle(moved.pose.theta - pose_.theta);
    const double heading = pose_.theta + 0.5 * dtheta;
    v = ((moved.pose.x - pose_.x) * std::cos(heading) + (moved.pose.y - pose_.y) * std::sin(heading)) / dt;
    w = dtheta / dt;
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
  pose_ = moved.pose;
  pose_.theta = wrapAngle(pose_.theta);
  v_ = v;
  w_ = w;
  // Contact for the bumpers: the nearest obstacle within the margin, located on the outline.
  const Contact touch = nearestContact(footprint_, pose_, obstacles);
  contact_ = touch.clearance <= kContactMargin;
  if (contact_)
    contact_angle_ = wrapAngle(std::atan2(touch.point.y - pose_.y, touch.point.x - pose_.x) - pose_.theta);
}

}  // namespace robot_sim
