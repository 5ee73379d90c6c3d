// Follows a sampled curve (HermitePath::sample) forwards. Steering is the curve's own
// curvature (feedforward) plus feedback on the lateral and heading errors from the closest
// point, tuned as a critically damped approach over `convergence_distance` whatever the speed:
//   w = v * kappa + v * e_y / D^2 + 2 * max(v, v_h) / D * e_theta
// v_h (`heading_correction_speed`) keeps the heading feedback alive when the robot is slow: in
// a sharp bend (a checkpoint the curve leaves almost backwards) the bend's speed limit is a few
// cm/s, the motor lag leaves the heading behind the tangent, and with a gain proportional to v
// that error is still there when the robot speeds up on the way out, which carries it off the
// curve. With the floor, the robot turns onto the tangent on the spot.
// kappa is taken `lookahead_time` ahead along the curve (at the current speed): the wheels
// answer a command only after the motor and pipeline lag, so steering for the bend that is
// reached then keeps the robot on the curve where the curvature changes (bend entries/exits).
// Speed comes from the Autopilot's speed curve on the arc length left, capped so every bend
// ahead can be taken under `max_lateral_accel` and the turn-rate limit. Past the end of the
// curve the reference is the final tangent, so the robot arrives on it without weaving.
// A robot that reaches the end along the tangent but more than `tolerance` beside it cannot
// close that by driving along the tangent (the lateral term needs distance to act): the
// Autopilot then takes it onto the end point (turn, creep, turn back to the end's heading), as
// a goto would. Without that the follower would stand beside a path's end for ever.
// Pure computation, tested without ROS.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "hal_nodes/driver/autopilot.h"
#include "hal_nodes/driver/hermite_path.h"

namespace hal_nodes {
namespace driver {

struct PathFollowerConfig {
  double convergence_distance = 0.15; // [m] distance over which an offset from the curve is taken back
  double sample_step = 0.005;    // [m] spacing of the curve's samples
  double max_lateral_accel = 0.3;  // [m/s^2] speed in bends: v^2 * curvature stays under it
  double lookahead_time = 0.0;     // [s] feed-forward curvature taken this far ahead (the actuation lag)
  double heading_correction_speed = 0.2;  // [m/s] slower than this, heading errors are corrected as at this speed

  std::string invalidReason() const;  // empty when usable
};

class PathFollower {
 public:
  PathFollower(const AutopilotConfig& base, const PathFollowerConfig& config) : base_(base), config_(config), finish_(base) {}

  // Follow `samples` (non-empty) to its last point within `tolerance`; max_speed 0: the limit.
  void start(std::vector<PathSample> samples, double tolerance, double max_speed);
  Twist2D step(const Pose2D& pose, const Twist2D& current);

  bool done() const { return done_; }
  bool active() const { return !samples_.empty() && !done_; }
  double remaining() const { return remaining_; }        // arc length left [m]
  double crossTrackError() const { return cross_track_; }  // distance to the curve [m]
  double progressPercent() const;
  // Segments fully behind the robot: checkpoint i is passed once segment() > i.
  int segment() const;
  const std::vector<PathSample>& samples() const { return samples_; }
  std::size_t index() const { return index_; }

 private:
  AutopilotConfig base_;
  PathFollowerConfig config_;
  Autopilot finish_;  // onto the end point when the curve's end was reached beside it
  std::vector<PathSample> samples_;
  std::size_t index_ = 0;
  double tolerance_ = 0.01, max_speed_ = 0.0, remaining_ = 0.0, cross_track_ = 0.0;
  bool settling_ = false, finishing_ = false, done_ = true;
};

}  // namespace driver
}  // namespace hal_nodes
