// Dead reckoning of a differential-drive robot: integrates (distance, heading change)
// increments along exact arcs and propagates the pose covariance, so the uncertainty grows
// with the distance travelled (each increment adds its own variance).
#pragma once

#include <Eigen/Core>
#include <robot_core/geometry.h>

namespace hal_nodes {

using robot_core::Pose2D;

// One odometry step: distance travelled by the wheel axis centre and heading change, with
// the variances of both (independent).
struct OdometryIncrement {
  double ds = 0.0;      // [m]
  double dtheta = 0.0;  // [rad]
  double var_ds = 0.0;  // [m^2]
  double var_dtheta = 0.0;  // [rad^2]
};

class PoseIntegrator {
 public:
  PoseIntegrator() { cov_.setZero(); }
  void add(const OdometryIncrement& inc);
  void reset(const Pose2D& pose = Pose2D());

  const Pose2D& pose() const { return pose_; }
  const Eigen::Matrix3d& covariance() const { return cov_; }  // over (x, y, theta)
  double distance() const { return distance_; }                  // total |ds| [m]

 private:
  Pose2D pose_;
  Eigen::Matrix3d cov_;
  double distance_ = 0.0;
};

using robot_core::wrapAngle;

}  // namespace hal_nodes
