#include "robot_sim/world/diff_drive.h"

#include <algorithm>
#include <cmath>

namespace robot_sim {

Pose2D integrateTwist(const Pose2D& p, double v, double w, double dt) {
  Pose2D out;
  const double dth = w * dt;
  if (std::abs(dth) < 1e-9) {
    // Straight (second-order midpoint keeps tiny arcs accurate).
    const double th = p.theta + 0.5 * dth;
    out.x = p.x + v * dt * std::cos(th);
    out.y = p.y + v * dt * std::sin(th);
  } else {
    const double r = v / w;
    out.x = p.x + r * (std::sin(p.theta + dth) - std::sin(p.theta));
    out.y = p.y - r * (std::cos(p.theta + dth) - std::cos(p.theta));
  }
  out.theta = wrapAngle(p.theta + dth);
  return out;
}

void wheelsToTwist(double v_left, double v_right, double wheel_base, double& v, double& w) {
  v = 0.5 * (v_left + v_right);
  w = (v_right - v_left) / wheel_base;
}

double slipFraction(const SlipConfig& c, double surface_speed, double surface_accel, double extra, Rng& rng) {
  if (std::abs(surface_speed) < 1e-6) return 0.0;
  const double along = surface_speed > 0 ? surface_accel : -surface_accel;  // > 0: speeding up
  const double s = c.per_accel * along + rng.gaussian(c.noise_std) + extra;
  return std::clamp(s, -c.max, std::max(c.max, extra));
}

}  // namespace robot_sim
