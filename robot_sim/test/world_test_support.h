// Helpers shared by the world's tests.
#pragma once

#include <cmath>

#include "robot_sim/world/sim_world.h"

namespace robot_sim {

// Steps the world for `seconds` of simulated time.
inline void run(SimWorld& w, double seconds) {
  const long n = std::lround(seconds / w.dt());
  for (long i = 0; i < n; ++i) w.step();
}

// Two drive motors, "left" and "right", quick and strong enough for any test drive, and wheels
// that do not slip: a test's robot moves exactly as commanded.
inline void addGripDriveMotors(WorldConfig& c) {
  MotorConfig m;
  m.max_speed = 20.0;
  m.time_constant = 0.05;
  m.max_accel = 60.0;
  m.drive = "left";
  c.robot.motors["left"] = m;
  m.drive = "right";
  c.robot.motors["right"] = m;
  c.robot.slip.per_accel = 0.0;
  c.robot.slip.noise_std = 0.0;
}

}  // namespace robot_sim
