// Relative movement from odometry alone (the `go_straight` and `rotate_by` actions): for
// precise final positioning and for getting free of a border when the map position is not
// trusted. Same control curves and limits as the Autopilot; poses are in the odom frame.
#pragma once

#include "hal_nodes/driver/autopilot.h"

namespace hal_nodes {
namespace driver {

// Drive a signed distance along the heading held at the start (negative: backwards).
class StraightMove {
 public:
  explicit StraightMove(const AutopilotConfig& config) : config_(config) {}
  void start(const Pose2D& from, double distance, double tolerance, double max_speed);
  Twist2D step(const Pose2D& pose, const Twist2D& current);
  bool done() const { return done_; }
  double remaining() const { return remaining_; }  // signed [m]
  double progressPercent() const;

 private:
  AutopilotConfig config_;
  Pose2D start_;
  double distance_ = 0.0, tolerance_ = 0.0, max_speed_ = 0.0, remaining_ = 0.0;
  bool settling_ = false, done_ = true;
};

// Turn in place by a signed angle, any size (2*pi is a full turn): odometry increments are
// accumulated, so the angle is not wrapped.
class Rotation {
 public:
  explicit Rotation(const AutopilotConfig& config) : config_(config) {}
  void start(const Pose2D& from, double angle, double tolerance, double max_speed);
  Twist2D step(const Pose2D& pose, const Twist2D& current);
  bool done() const { return done_; }
  double remaining() const { return angle_ - turned_; }  // signed [rad]
  double progressPercent() const;

 private:
  AutopilotConfig config_;
  double last_theta_ = 0.0, angle_ = 0.0, turned_ = 0.0, tolerance_ = 0.0, max_speed_ = 0.0;
  bool settling_ = false, done_ = true;
};

}  // namespace driver
}  // namespace hal_nodes
