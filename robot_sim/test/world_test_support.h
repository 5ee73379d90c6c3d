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

}  // namespace robot_sim
