#include "hal_nodes/devices/drive/wheel_speeds.h"

#include <algorithm>
#include <cmath>

namespace hal_nodes {

WheelSpeeds wheelSpeeds(double v, double w, double track_width, double max_wheel_speed) {
  if (!std::isfinite(v) || !std::isfinite(w)) return WheelSpeeds();
  WheelSpeeds s{v - 0.5 * w * track_width, v + 0.5 * w * track_width};
  const double peak = std::max(std::abs(s.left), std::abs(s.right));
  if (peak > max_wheel_speed && peak > 0.0) {
    const double k = max_wheel_speed / peak;
    s.left *= k;
    s.right *= k;
  }
  return s;
}

WheelSpeeds rampTowards(const WheelSpeeds& current, const WheelSpeeds& target, double max_acceleration, double dt) {
  if (max_acceleration <= 0.0 || dt <= 0.0) return target;
  const double dl = target.left - current.left;
  const double dr = target.right - current.right;
  const double peak = std::max(std::abs(dl), std::abs(dr));
  const double step = max_acceleration * dt;
  if (peak <= step) return target;
  const double k = step / peak;
  return WheelSpeeds{current.left + k * dl, current.right + k * dr};
}

int nativeValue(double speed, double units_per_mps, int max_value) {
  const double v = std::round(speed * units_per_mps);
  if (!std::isfinite(v)) return 0;
  return static_cast<int>(std::clamp(v, -static_cast<double>(max_value), static_cast<double>(max_value)));
}

}  // namespace hal_nodes
