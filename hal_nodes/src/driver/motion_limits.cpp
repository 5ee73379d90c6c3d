#include "hal_nodes/driver/motion_limits.h"

#include <algorithm>
#include <cmath>

namespace hal_nodes {
namespace driver {

namespace {
bool positive(double x) { return x > 0.0 && std::isfinite(x); }
}  // namespace

std::string MotionLimits::invalidReason() const {
  if (!positive(max_linear_speed)) return "max_linear_speed must be > 0";
  if (!positive(max_angular_speed)) return "max_angular_speed must be > 0";
  if (!positive(max_linear_accel)) return "max_linear_accel must be > 0";
  if (!positive(max_angular_accel)) return "max_angular_accel must be > 0";
  if (!positive(max_wheel_speed)) return "max_wheel_speed must be > 0";
  if (!positive(track_width)) return "track_width must be > 0";
  return "";
}

Twist2D VelocityLimiter::clampSpeed(const Twist2D& desired) const {
  Twist2D c;
  c.v = std::isfinite(desired.v) ? std::clamp(desired.v, -limits_.max_linear_speed, limits_.max_linear_speed) : 0.0;
  c.w = std::isfinite(desired.w) ? std::clamp(desired.w, -limits_.max_angular_speed, limits_.max_angular_speed) : 0.0;
  // Keep the outer wheel under its limit by scaling both (same curvature, slower).
  const double wheel = std::fabs(c.v) + std::fabs(c.w) * limits_.track_width / 2.0;
  if (wheel > limits_.max_wheel_speed) {
    const double k = limits_.max_wheel_speed / wheel;
    c.v *= k;
    c.w *= k;
  }
  return c;
}

Twist2D VelocityLimiter::apply(const Twist2D& desired, double dt) {
  const Twist2D target = clampSpeed(desired);
  const double dv = target.v - last_.v;
  const double dw = target.w - last_.w;
  double k = 1.0;
  if (dt > 0.0) {
    const double max_dv = limits_.max_linear_accel * dt;
    const double max_dw = limits_.max_angular_accel * dt;
    if (std::fabs(dv) > max_dv) k = std::min(k, max_dv / std::fabs(dv));
    if (std::fabs(dw) > max_dw) k = std::min(k, max_dw / std::fabs(dw));
  } else {
    k = 0.0;  // no time passed: no change allowed
  }
  Twist2D out{last_.v + k * dv, last_.w + k * dw};
  // Snap tiny residues to exact zero so "stopped" is a clean test.
  if (std::fabs(out.v) < 1e-9) out.v = 0.0;
  if (std::fabs(out.w) < 1e-9) out.w = 0.0;
  last_ = out;
  return out;
}

}  // namespace driver
}  // namespace hal_nodes
