// Differential-drive odometry noise: the proposal that spreads particles so the cloud does not
// outrun a slipping robot. Per particle and per increment
// (ds forward, dl lateral, dtheta in the robot frame):
//   ds' = ds + N(0, trans_per_trans*|ds| + trans_per_rot*|dtheta|)
//   dl' = dl + N(0, lateral_per_trans*|ds|)
//   dtheta' = dtheta + N(0, rot_per_trans*|ds| + rot_per_rot*|dtheta|)
// plus wheel slips: an increment the odometry found slipping (see slip_accel) gets
// dtheta' += N(0, slip_rot) on every particle; slips it cannot see are a heavy tail, with
// probability slip_probability per increment the robot travelled less than the encoders say,
// ds' -= |N(0, slip_trans)|, and dtheta' += N(0, slip_rot).
#pragma once

#include "hal_nodes/mcl/particle_set.h"
#include "hal_nodes/mcl/pose.h"
#include "hal_nodes/mcl/rng.h"

namespace hal_nodes::mcl {

struct MotionModel {
  // Defaults: encoders good to ~1 % of travel and 0.2 rad of heading per metre, with slips
  // (the 2009 robot's wheels; the bench runs are generated with the same figures).
  double trans_per_trans = 0.01;     // [m/m]
  double trans_per_rot = 0.001;      // [m/rad]
  double lateral_per_trans = 0.001;  // [m/m]
  double rot_per_trans = 0.2;        // [rad/m]
  double rot_per_rot = 0.005;        // [rad/rad]
  double slip_probability = 0.01;    // per increment, slips the detection below does not see
  double slip_trans = 0.0075;        // [m]
  double slip_rot = 0.01;            // [rad]
  // Slip detection (odometry_input.h): an encoder pair whose travel exceeds what the robot can
  // have done at its last speed plus slip_accel (more than the tyres' grip allows, ~0.5 g)
  // by more than slip_margin (encoder resolution and noise) has a wheel spinning. 0 disables.
  double slip_accel = 5.0;           // [m/s^2]
  double slip_margin = 0.001;        // [m]

  // Throws std::invalid_argument naming the bad field.
  void validate() const;
  // Apply the increment `d` (robot frame) with per-particle noise.
  // `slipping`: the increment is known to come from a slip (detected by the odometry): every
  // particle gets the slip's heading noise instead of a slip_probability share of them.
  void apply(ParticleSet& set, const Pose2D& d, Rng& rng, bool slipping = false) const;
};

}  // namespace hal_nodes::mcl
