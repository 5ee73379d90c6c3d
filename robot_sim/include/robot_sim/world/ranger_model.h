// SRF02 (ultrasonic, wide cone) and SHARP (infrared, narrow beam) rangers: the nearest
// obstacle point anywhere in the beam (exact, robot_core::TableGeometry::coneRange), with Gaussian
// noise growing with range. Nothing within max_range reads +inf (REP-117 "no return").
#pragma once

#include <vector>

#include "robot_sim/world/config.h"
#include "robot_sim/world/random.h"
#include "robot_sim/world/table_geometry.h"

namespace robot_sim {

// The true range (no noise) seen by `ranger` on a robot at `robot`.
double trueRange(const RangerConfig& ranger, const Pose2D& robot, const TableGeometry& table,
                 const std::vector<Circle>& obstacles);

// A measurement: the true range with noise, clamped to [min_range, max_range]; +inf if nothing.
double noisyRange(const RangerConfig& ranger, double true_range, Rng& rng);

}  // namespace robot_sim
