#include "hal_nodes/driver/relative_moves.h"

#include <algorithm>
#include <cmath>

namespace hal_nodes {
namespace driver {

namespace {
// Curve, capped by what the brake can still stop from: |command| for a remaining error.
double curveSpeed(const ControlCurve& curve, double remaining, double max_speed, double decel) {
  return std::min(max_speed * std::fabs(curve.fraction(remaining)), brakingSpeed(std::fabs(remaining), decel));
}
double percent(double done, double total) {
  return total > 0.0 ? 100.0 * std::clamp(done / total, 0.0, 1.0) : 100.0;
}
}  // namespace

void StraightMove::start(const Pose2D& from, double distance, double tolerance, double max_speed) {
  start_ = from;
  distance_ = distance;
  tolerance_ = tolerance;
  max_speed_ = max_speed > 0.0 ? std::min(max_speed, config_.limits.max_linear_speed) : config_.limits.max_linear_speed;
  remaining_ = distance;
  settling_ = false;
  done_ = false;
}

Twist2D StraightMove::step(const Pose2D& pose, const Twist2D& current) {
  if (done_) return Twist2D();
  const double along = (pose.x - start_.x) * std::cos(start_.theta) + (pose.y - start_.y) * std::sin(start_.theta);
  remaining_ = distance_ - along;
  if (!settling_ && std::fabs(remaining_) <= 0.5 * tolerance_) settling_ = true;
  if (settling_ && std::fabs(remaining_) > tolerance_) settling_ = false;
  if (settling_) {
    if (current.v == 0.0 && current.w == 0.0) done_ = true;
    return Twist2D();
  }
  const MotionLimits& lim = config_.limits;
  const double heading_error = wrapAngle(start_.theta - pose.theta);  // hold the start heading
  Twist2D cmd;
  cmd.v = sign(remaining_) * curveSpeed(config_.speed_curve, remaining_, max_speed_, 0.9 * lim.max_linear_accel);
  cmd.w = sign(heading_error) *
          curveSpeed(config_.turn_curve, heading_error, lim.max_angular_speed, 0.9 * lim.max_angular_accel);
  return cmd;
}

double StraightMove::progressPercent() const {
  return done_ ? 100.0 : percent(std::fabs(distance_) - std::fabs(remaining_), std::fabs(distance_));
}

void Rotation::start(const Pose2D& from, double angle, double tolerance, double max_speed) {
  last_theta_ = from.theta;
  angle_ = angle;
  turned_ = 0.0;
  tolerance_ = tolerance;
  max_speed_ = max_speed > 0.0 ? std::min(max_speed, config_.limits.max_angular_speed) : config_.limits.max_angular_speed;
  settling_ = false;
  done_ = false;
}

Twist2D Rotation::step(const Pose2D& pose, const Twist2D& current) {
  if (done_) return Twist2D();
  turned_ += wrapAngle(pose.theta - last_theta_);  // increments are small at the control rate
  last_theta_ = pose.theta;
  const double r = remaining();
  if (!settling_ && std::fabs(r) <= 0.5 * tolerance_) settling_ = true;
  if (settling_ && std::fabs(r) > tolerance_) settling_ = false;
  if (settling_) {
    if (current.v == 0.0 && current.w == 0.0) done_ = true;
    return Twist2D();
  }
  return Twist2D{0.0, sign(r) * curveSpeed(config_.turn_curve, r, max_speed_, 0.9 * config_.limits.max_angular_accel)};
}

double Rotation::progressPercent() const {
  return done_ ? 100.0 : percent(std::fabs(angle_) - std::fabs(remaining()), std::fabs(angle_));
}

}  // namespace driver
}  // namespace hal_nodes
