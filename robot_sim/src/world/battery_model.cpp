#include "robot_sim/world/battery_model.h"

#include <algorithm>

namespace robot_sim {

double batteryVoltage(const BatteryConfig& c, double elapsed, double total_current, Rng& rng) {
  const double open = c.full - (c.full - c.empty) * std::clamp(elapsed / c.life, 0.0, 1.0);
  return std::max(0.0, open - c.internal_resistance * total_current + rng.gaussian(c.noise_std));
}

}  // namespace robot_sim
