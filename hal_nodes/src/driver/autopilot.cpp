#include "hal_nodes/driver/autopilot.h"

#include <algorithm>
#include <cmath>

namespace hal_nodes {
namespace driver {

std::string AutopilotConfig::invalidReason() const {
  std::string r = speed_curve.invalidReason();
  if (!r.empty()) return "speed_curve: " + r;
  r = turn_curve.invalidReason();
  if (!r.empty()) return "turn_curve: " + r;
  r = limits.invalidReason();
  if (!r.empty()) return "limits: " + r;
  if (!(turn_in_place_angle > 0.0 && turn_in_place_angle <= M_PI)) return "turn_in_place_angle must be in (0, pi]";
  if (!(near_radius >= 0.0 && near_radius < 1.0)) return "near_radius must be in [0, 1)";
  return "";
}

const char* Autopilot::phaseName(Phase p) {
  switch (p) {
    case Phase::TURN: return "turning to the target";
    case Phase::DRIVE: return "driving";
    case Phase::ROTATE: return "turning to the final heading";
    case Phase::SETTLE: return "stopping";
    case Phase::DONE: return "done";
  }
  return "?";
}

void Autopilot::start(const AutopilotGoal& goal, const Pose2D& from) {
  goal_ = goal;
  const double dx = goal.target.x - from.x, dy = goal.target.y - from.y;
  start_distance_ = std::hypot(dx, dy);
  start_angle_ = std::fabs(wrapAngle(goal.target.theta - from.theta));
  const double bearing_error = wrapAngle(std::atan2(dy, dx) - from.theta);
  direction_ = (goal.allow_reverse && std::fabs(bearing_error) > M_PI / 2.0) ? -1 : 1;
  remaining_ = start_distance_;
  progress_ = 0.0;
  phase_ = Phase::TURN;
}

Twist2D Autopilot::turnTo(double error, double max_speed) const {
  const double decel = 0.9 * config_.limits.max_angular_accel;
  const double w = std::min(max_speed * std::fabs(config_.turn_curve.fraction(error)), brakingSpeed(std::fabs(error), decel));
  return Twist2D{0.0, sign(error) * w};
}

Twist2D Autopilot::step(const Pose2D& pose, const Twist2D& current, const Twist2D* measured) {
  if (phase_ == Phase::DONE) return Twist2D();
  const MotionLimits& lim = config_.limits;
  const double tol = goal_.position_tolerance;
  const double dx = goal_.target.x - pose.x, dy = goal_.target.y - pose.y;
  const double d = std::hypot(dx, dy);
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  const double along = direction_ * (dx * c + dy * s);  // still to go along the driving direction
  const double lateral = -dx * s + dy * c;
  const double facing = direction_ < 0 ? pose.theta + M_PI : pose.theta;
  const double bearing_error = d > 1e-9 ? wrapAngle(std::atan2(dy, dx) - facing) : 0.0;
  // Near the target: align the axis with the target either way (a small reverse beats a U-turn).
  double axis_error = bearing_error;
  if (axis_error > M_PI / 2.0) axis_error -= M_PI;
  if (axis_error < -M_PI / 2.0) axis_error += M_PI;
  const bool near = d < config_.near_radius;
  const bool any_heading = !goal_.final_heading || goal_.angle_tolerance >= M_PI;
  const double final_error = wrapAngle(goal_.target.theta - pose.theta);
  remaining_ = d;
  heading_error_ = near ? axis_error : bearing_error;

  // Phase changes.
  if (phase_ == Phase::TURN || phase_ == Phase::DRIVE) {
    const bool arrived = goal_.final_heading ? (d <= 0.5 * tol || (d <= tol && along <= 0.0)) : d <= tol;
    if (arrived) {
      if (!goal_.final_heading) {
        phase_ = Phase::DONE;
        return Twist2D();
      }
      phase_ = Phase::ROTATE;
    }
  } else if (d > 2.0 * tol) {
    phase_ = Phase::TURN;  // pushed off the target: go back
  }
  if (phase_ == Phase::TURN) {
    if (near ? std::fabs(lateral) <= 0.5 * tol : std::fabs(bearing_error) <= 0.5 * config_.turn_in_place_angle)
      phase_ = Phase::DRIVE;
  } else if (phase_ == Phase::DRIVE) {
    if (near ? std::fabs(lateral) > tol : std::fabs(bearing_error) > config_.turn_in_place_angle) phase_ = Phase::TURN;
  }
  if (phase_ == Phase::ROTATE && (any_heading || std::fabs(final_error) <= 0.5 * goal_.angle_tolerance))
    phase_ = Phase::SETTLE;
  if (phase_ == Phase::SETTLE && !any_heading && std::fabs(final_error) > goal_.angle_tolerance) phase_ = Phase::ROTATE;

  // Progress: distance covered, or heading turned for a goal that is only a rotation.
  if (start_distance_ > tol)
    progress_ = 100.0 * std::clamp(1.0 - d / start_distance_, 0.0, 1.0);
  else if (!any_heading && start_angle_ > 0.0)
    progress_ = 100.0 * std::clamp(1.0 - std::fabs(final_error) / start_angle_, 0.0, 1.0);

  const double vmax = goal_.max_speed > 0.0 ? std::min(goal_.max_speed, lim.max_linear_speed) : lim.max_linear_speed;
  const double decel = 0.9 * lim.max_linear_accel;
  switch (phase_) {
    case Phase::TURN:
      return turnTo(near ? axis_error : bearing_error, lim.max_angular_speed);
    case Phase::DRIVE: {
      if (near) {
        const double dist = std::fabs(along);
        const double speed = std::min(vmax * config_.speed_curve.fraction(dist), brakingSpeed(dist, decel));
        return Twist2D{direction_ * sign(along) * speed, 0.0};
      }
      const double slow = std::max(0.0, 1.0 - std::fabs(bearing_error) / config_.turn_in_place_angle);
      const double speed = std::min(vmax * config_.speed_curve.fraction(d), brakingSpeed(d, decel)) * slow;
      return Twist2D{direction_ * speed, turnTo(bearing_error, lim.max_angular_speed).w};
    }
    case Phase::ROTATE:
      return turnTo(final_error, lim.max_angular_speed);
    case Phase::SETTLE:
      if (current.v == 0.0 && current.w == 0.0) {
        if (measured && (std::fabs(measured->v) > 0.005 || std::fabs(measured->w) > 0.02)) return Twist2D();  // still rolling
        if (d > tol) {  // stopped outside the tolerance (rolled on): approach again
          phase_ = Phase::TURN;
          return Twist2D();
        }
        if (!any_heading && std::fabs(final_error) > goal_.angle_tolerance) {
          phase_ = Phase::ROTATE;
          return Twist2D();
        }
        phase_ = Phase::DONE;
        progress_ = 100.0;
      }
      return Twist2D();
    case Phase::DONE:
      break;
  }
  return Twist2D();
}

}  // namespace driver
}  // namespace hal_nodes
