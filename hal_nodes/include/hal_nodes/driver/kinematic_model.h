// A simple differential-drive base for the driver's unit tests and the kinematic benchmark
// (not used by the product): the command reaches the wheels `delay` periods late (the
// HAL -> HCL -> board path) and through a first-order lag of `time_constant` (the motor),
// then the pose integrates exactly along the arc.
#pragma once

#include <cmath>
#include <deque>

#include "hal_nodes/driver/geometry.h"

namespace hal_nodes {
namespace driver {

class KinematicModel {
 public:
  KinematicModel(const Pose2D& start, int delay = 1, double time_constant = 0.02)
      : pose_(start), delay_(delay), tau_(time_constant) {}

  void step(const Twist2D& command, double dt) {
    queue_.push_back(command);
    Twist2D cmd;
    if (static_cast<int>(queue_.size()) > delay_) {
      cmd = queue_.front();
      queue_.pop_front();
    }
    const double k = tau_ > 0.0 ? 1.0 - std::exp(-dt / tau_) : 1.0;
    vel_.v += k * (cmd.v - vel_.v);
    vel_.w += k * (cmd.w - vel_.w);
    const double dth = vel_.w * dt;
    if (std::fabs(dth) < 1e-9) {
      pose_.x += vel_.v * dt * std::cos(pose_.theta);
      pose_.y += vel_.v * dt * std::sin(pose_.theta);
    } else {
      const double r = vel_.v / vel_.w;
      pose_.x += r * (std::sin(pose_.theta + dth) - std::sin(pose_.theta));
      pose_.y -= r * (std::cos(pose_.theta + dth) - std::cos(pose_.theta));
    }
    pose_.theta = wrapAngle(pose_.theta + dth);
  }

  const Pose2D& pose() const { return pose_; }
  const Twist2D& velocity() const { return vel_; }
  // Wheels stopped: under 5 mm/s of speed and 0.02 rad/s of turn.
  bool stopped() const { return std::fabs(vel_.v) < 0.005 && std::fabs(vel_.w) < 0.02; }

 private:
  Pose2D pose_;
  Twist2D vel_;
  int delay_;
  double tau_;
  std::deque<Twist2D> queue_;
};

}  // namespace driver
}  // namespace hal_nodes
