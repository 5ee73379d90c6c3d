// The battery: open-circuit voltage falling linearly over its life, minus the sag of the
// motors' current through the internal resistance, plus measurement noise.
#pragma once

#include "robot_sim/world/config.h"
#include "robot_sim/world/random.h"

namespace robot_sim {

double batteryVoltage(const BatteryConfig& config, double elapsed, double total_current, Rng& rng);

}  // namespace robot_sim
