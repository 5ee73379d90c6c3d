// Position actuators of the robot's mechanisms: an RC servo slews to its target at a bounded
// speed; a stepper moves one step at a time at its step rate. Both clamp to their travel.
#pragma once

#include <cstdint>

#include "robot_sim/world/config.h"

namespace robot_sim {

struct ServoState {
  double target = 0.0, position = 0.0;
};
struct StepperState {
  int64_t target = 0, position = 0;
  double phase = 0.0;  // fraction of the next step already elapsed
};

void stepServo(const ServoConfig& config, ServoState& state, double dt);
void stepStepper(const StepperConfig& config, StepperState& state, double dt);

}  // namespace robot_sim
