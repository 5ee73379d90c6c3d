#include "robot_sim/world/motor_model.h"

#include <algorithm>
#include <cmath>

namespace robot_sim {

double motorCurrent(const MotorConfig& c, double u, double w) {
  // I = (V - k w) / R, in units of the stall current at full voltage.
  return c.stall_current * (u - w / c.max_speed);
}

void stepMotor(const MotorConfig& c, MotorState& s, double dt, bool blocked) {
  const double raw = std::clamp(s.command, -1.0, 1.0) * (c.inverted ? -1.0 : 1.0);
  // Below the dead band the motor does not turn; above it the command spans the rest.
  const double u = c.dead_band > 0.0 ? std::copysign(std::max(0.0, std::abs(raw) - c.dead_band) / (1.0 - c.dead_band), raw)
                                     : raw;
  if (blocked) {
    const double i = std::clamp(motorCurrent(c, u, 0.0), -c.current_limit, c.current_limit);
    s.accel = -s.speed / dt;
    s.speed = 0.0;
    s.current = i;
    return;
  }
  // The limiter keeps |I| <= limit by lowering the effective command around the back-EMF.
  const double back = s.speed / c.max_speed;
  const double margin = c.current_limit / c.stall_current;
  const double u_eff = back + std::clamp(u - back, -margin, margin);
  const double target = u_eff * c.max_speed;
  // First-order lag, exact over the step, then the acceleration bound.
  double next = target + (s.speed - target) * std::exp(-dt / c.time_constant);
  const double dv_max = c.max_accel * dt;
  next = std::clamp(next, s.speed - dv_max, s.speed + dv_max);
  s.accel = (next - s.speed) / dt;
  s.speed = next;
  const double i = motorCurrent(c, u_eff, s.speed);
  s.current = i + (std::abs(s.speed) > 1e-6 ? std::copysign(c.no_load_current, s.speed) : 0.0);
}

}  // namespace robot_sim
