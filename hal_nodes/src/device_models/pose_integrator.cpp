#include "hal_nodes/devices/odometry/pose_integrator.h"

#include <Eigen/Dense>
#include <cmath>

namespace hal_nodes {

void PoseIntegrator::reset(const Pose2D& pose) {
  pose_ = pose;
  cov_.setZero();
  distance_ = 0.0;
}

void PoseIntegrator::add(const OdometryIncrement& inc) {
  const double th = pose_.theta;
  const double mid = th + 0.5 * inc.dtheta;
  // Exact arc for the mean (a chord along the mid heading scaled by the chord/arc ratio).
  const double half = 0.5 * inc.dtheta;
  const double chord = std::abs(half) < 1e-9 ? inc.ds : inc.ds * std::sin(half) / half;
  pose_.x += chord * std::cos(mid);
  pose_.y += chord * std::sin(mid);
  pose_.theta = wrapAngle(th + inc.dtheta);
  distance_ += std::abs(inc.ds);

  // First-order covariance propagation (mid-heading linearisation).
  Eigen::Matrix3d Jx = Eigen::Matrix3d::Identity();
  Jx(0, 2) = -chord * std::sin(mid);
  Jx(1, 2) = chord * std::cos(mid);
  Eigen::Matrix<double, 3, 2> Ju;
  Ju << std::cos(mid), -0.5 * inc.ds * std::sin(mid),  //
      std::sin(mid), 0.5 * inc.ds * std::cos(mid),     //
      0.0, 1.0;
  Eigen::Matrix2d Q = Eigen::Matrix2d::Zero();
  Q(0, 0) = inc.var_ds;
  Q(1, 1) = inc.var_dtheta;
  cov_ = Jx * cov_ * Jx.transpose() + Ju * Q * Ju.transpose();
}

}  // namespace hal_nodes
