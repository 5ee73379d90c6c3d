// The pose the localization publishes: the filter's estimate carried forward to the newest
// odometry. The filter steps through its inputs only ~latency behind the newest odometry
// (input_events.h: what keeps a replay deterministic), so its own estimate is that old when it
// is computed; the odometry received since then moves it to the present. What is published at
// a stamp depends only on the inputs up to that stamp, so a replay still gives the same pose
// at the same stamp. The covariance stays the filter's: the odometry's noise over ~latency is
// far below the particle spread it is added to.
#pragma once

#include "hal_nodes/mcl/pose.h"

namespace hal_nodes::localization {

// `estimate` (map -> base_link) was computed with odometry `odom_at_estimate` (odom ->
// base_link); the robot has since moved to `odom_now`: the estimate at odom_now's stamp.
inline mcl::Pose2D carryForward(const mcl::Pose2D& estimate, const mcl::Pose2D& odom_at_estimate,
                                const mcl::Pose2D& odom_now) {
  return mcl::compose(estimate, mcl::between(odom_at_estimate, odom_now));
}

// The newest odometry received, by stamp (an older message arriving late does not replace it).
class NewestOdometry {
 public:
  void offer(double stamp, const mcl::Pose2D& pose) {
    if (have_ && stamp < stamp_) return;
    have_ = true;
    stamp_ = stamp;
    pose_ = pose;
  }
  bool have() const { return have_; }
  double stamp() const { return stamp_; }
  const mcl::Pose2D& pose() const { return pose_; }

 private:
  bool have_ = false;
  double stamp_ = 0.0;
  mcl::Pose2D pose_;
};

}  // namespace hal_nodes::localization
