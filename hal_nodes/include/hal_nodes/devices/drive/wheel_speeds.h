// Differential-drive kinematics for the drive effector: a body velocity (v, w) becomes left
// and right wheel speeds; when a wheel would exceed its limit both are scaled down together
// so the robot keeps the commanded curvature (it slows down instead of turning differently).
// An optional acceleration limit ramps each wheel towards its target.
#pragma once

#include <utility>

namespace hal_nodes {

struct WheelSpeeds {
  double left = 0.0;   // [m/s]
  double right = 0.0;  // [m/s]
};

WheelSpeeds wheelSpeeds(double v, double w, double track_width, double max_wheel_speed);

// Move `current` towards `target` by at most max_acceleration * dt per wheel (0: no limit),
// keeping the ratio between the wheels so a ramp does not bend the path.
WheelSpeeds rampTowards(const WheelSpeeds& current, const WheelSpeeds& target, double max_acceleration, double dt);

// A wheel speed in the board's native unit, rounded and clamped to +-max_value.
int nativeValue(double speed, double units_per_mps, int max_value);

}  // namespace hal_nodes
