#include "robot_sim/world/actuators.h"

#include <algorithm>
#include <cmath>

namespace robot_sim {

void stepServo(const ServoConfig& c, ServoState& s, double dt) {
  const double target = std::clamp(s.target, c.min, c.max);
  const double d = std::clamp(target - s.position, -c.speed * dt, c.speed * dt);
  s.position += d;
}

void stepStepper(const StepperConfig& c, StepperState& s, double dt) {
  const int64_t target = std::clamp(s.target, c.min, c.max);
  if (target == s.position) {
    s.phase = 0.0;
    return;
  }
  s.phase += c.steps_per_second * dt;
  const int64_t n = static_cast<int64_t>(std::floor(s.phase));
  s.phase -= static_cast<double>(n);
  const int64_t left = target - s.position;
  s.position += left > 0 ? std::min(n, left) : std::max(-n, left);
}

}  // namespace robot_sim
