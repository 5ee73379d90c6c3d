// A DC motor behind an H-bridge: the shaft speed follows the command with a first-order lag,
// bounded acceleration, and a current limiter that lowers the effective voltage when the
// current (proportional to command minus back-EMF) would exceed the limit.
#pragma once

#include "robot_sim/world/config.h"

namespace robot_sim {

struct MotorState {
  double command = 0.0;  // -1..1 as commanded (before `inverted`)
  double speed = 0.0;    // output shaft = wheel speed [rad/s], wheel-forward positive
  double accel = 0.0;    // of the last step [rad/s^2]
  double current = 0.0;  // [A], signed
};

// Advances one step of dt. `blocked`: the shaft cannot turn (the robot is pressed against an
// obstacle), so the speed is forced to zero and the current is the stall current (limited).
void stepMotor(const MotorConfig& config, MotorState& state, double dt, bool blocked = false);

// The steady-state current for an effective command u at shaft speed w (before limiting).
double motorCurrent(const MotorConfig& config, double u, double w);

}  // namespace robot_sim
