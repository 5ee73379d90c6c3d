// A magnetic compass (CMPS03-like): heading clockwise from magnetic north, with a fixed bias
// (the robot's own iron) and Gaussian noise.
#pragma once

#include "robot_sim/world/config.h"
#include "robot_sim/world/random.h"

namespace robot_sim {

// Heading [deg] in [0, 360) for a robot with map-frame yaw `theta` [rad].
double trueCompassDeg(const CompassConfig& config, double theta);
double noisyCompassDeg(const CompassConfig& config, double theta, Rng& rng);

}  // namespace robot_sim
