// Differential-drive odometry noise: the proposal that spreads particles so the cloud does not
// outrun a slipping robot (the original work's point). Per particle and per increment
// (ds forward, dl lateral, dtheta in the robot frame):
//   ds' = ds + N(0, trans_per_trans*|ds| + trans_per_rot*|dtheta|)
//   dl' = dl + N(0, lateral_per_trans*|ds|)
//   dtheta' = dtheta + N(0, rot_per_trans*|ds| + rot_per_rot*|dtheta|)
// plus, with probability slip_probability per increment, a wheel slip: the robot travelled
// less than the encoders say, ds' -= |N(0, slip_trans)|, and dtheta' += N(0, slip_rot)
// (heavy tail: a slip is rare but large).
#pragma once

#include "hal_nodes/mcl/particle_set.h"
#include "hal_nodes/mcl/pose.h"
#include "hal_nodes/mcl/rng.h"

namespace hal_nodes::mcl {

struct MotionModel {
  // Defaults: encoders good to ~1 % of travel and 0.2 rad of heading per metre, with rare slips
  // (the 2009 robot's wheels; the bench runs are generated with the same figures).
  double trans_per_trans = 0.01;     // [m/m]
  double trans_per_rot = 0.001;      // [m/rad]
  double lateral_per_trans = 0.001;  // [m/m]
  double rot_per_trans = 0.2;        // [rad/m]
  double rot_per_rot = 0.005;        // [rad/rad]
  double slip_probability = 0.01;    // per increment
  double slip_trans = 0.0075;        // [m]
  double slip_rot = 0.01;            // [rad]

  // Throws std::invalid_argument naming the bad field.
  void validate() const;
  // Apply the increment `d` (robot frame) with per-particle noise.
  void apply(ParticleSet& set, const Pose2& d, Rng& rng) const;
};

}  // namespace hal_nodes::mcl
