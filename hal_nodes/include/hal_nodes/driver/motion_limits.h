// Velocity and acceleration limits of the base, and the limiter every controlled command goes
// through: the driver never commands more than these (config `hal/driver/limits`).
//
// The one exception is a stop (cancel, new goal, safety abort, deactivation): it commands zero
// at once, because "stop within one control period" is the safety requirement; the motor
// boards then brake as hard as their own firmware allows.
#pragma once

#include <string>

#include "hal_nodes/driver/geometry.h"

namespace hal_nodes {
namespace driver {

struct MotionLimits {
  double max_linear_speed = 0.5;     // [m/s]
  double max_angular_speed = 3.0;    // [rad/s]
  double max_linear_accel = 1.0;     // [m/s^2], also the deceleration
  double max_angular_accel = 6.0;    // [rad/s^2]
  double max_wheel_speed = 0.6;      // [m/s] |v| + |w| * track / 2 never exceeds it
  double track_width = 0.3;          // [m] distance between the driven wheels

  std::string invalidReason() const;  // empty when usable
};

class VelocityLimiter {
 public:
  explicit VelocityLimiter(const MotionLimits& limits) : limits_(limits) {}

  // The command to send this period: `desired` clamped to the speed limits (keeping the
  // curvature w/v when the wheel limit scales it), then moved from the last command by at most
  // accel * dt on each axis (both axes by the same fraction, so a stop stays on its curve).
  Twist2D apply(const Twist2D& desired, double dt);

  // Emergency stop / start over: the last command becomes `current` without any limit.
  void reset(const Twist2D& current = Twist2D()) { last_ = current; }
  const Twist2D& last() const { return last_; }
  const MotionLimits& limits() const { return limits_; }

  // Speeds clamped to the velocity limits only.
  Twist2D clampSpeed(const Twist2D& desired) const;

 private:
  MotionLimits limits_;
  Twist2D last_;
};

}  // namespace driver
}  // namespace hal_nodes
