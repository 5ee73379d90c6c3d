// Differential-drive kinematics and the wheel slip model.
#pragma once

#include <robot_core/geometry.h>

#include "robot_sim/world/config.h"
#include "robot_sim/world/random.h"

namespace robot_sim {

// Exact integration of a constant body twist (v forward [m/s], w [rad/s]) over dt.
Pose2D integrateTwist(const Pose2D& pose, double v, double w, double dt);

// Body twist from the ground speeds of the left and right wheel contact points.
void wheelsToTwist(double v_left, double v_right, double wheel_base, double& v, double& w);

// Slip fraction of a driven wheel: the contact moves at surface_speed * (1 - slip). It grows
// with the wheel's acceleration (positive while speeding up: the wheel spins faster than the
// ground; negative while braking: the ground runs ahead of the wheel), plus zero-mean noise
// while the wheel turns, plus `extra` (an injected hard slip), clamped to +-max.
double slipFraction(const SlipConfig& config, double surface_speed, double surface_accel, double extra, Rng& rng);

using robot_core::wrapAngle;

}  // namespace robot_sim
