// The map pose the driver controls on, now: the newest localization estimate (/mcl/pose, at
// its stamp) carried forward by odometry since that stamp. Localization runs slower than the
// control loop and arrives late; steering on its raw pose would lag by up to a period of the
// filter (5 cm at 0.5 m/s). Same maths as the map->odom transform, kept here so the driver does
// not depend on when the localization device publishes tf.
#pragma once

#include <cmath>
#include <deque>

#include "hal_nodes/driver/geometry.h"

namespace hal_nodes {
namespace driver {

using robot_core::compose;
using robot_core::inverse;

class PoseFusion {
 public:
  explicit PoseFusion(double history = 2.0) : history_(history) {}

  // Odometry pose at time t (seconds, increasing).
  void addOdometry(double t, const Pose2D& odom) {
    if (!odom_.empty() && t <= odom_.back().t) return;
    odom_.push_back({t, odom});
    while (odom_.size() > 2 && odom_.front().t < t - history_) odom_.pop_front();
  }

  // Localization estimate valid at time t: the map<-odom correction from the odometry then.
  void setMapPose(double t, const Pose2D& map) {
    Pose2D odom_then;
    if (!odometryAt(t, &odom_then)) {
      correction_ = map;  // no odometry: use the estimate as it is
      raw_ = true;
    } else {
      correction_ = compose(map, inverse(odom_then));
      raw_ = false;
    }
    has_ = true;
  }

  // The map pose now; false before the first estimate.
  bool mapPose(Pose2D* out) const {
    if (!has_) return false;
    *out = (raw_ || odom_.empty()) ? correction_ : compose(correction_, odom_.back().pose);
    return true;
  }

  // The map pose at time t (within the odometry history, e.g. when a ranger reading was taken);
  // false without an estimate or odometry then.
  bool mapPoseAt(double t, Pose2D* out) const {
    Pose2D odom_then;
    if (!has_ || raw_ || !odometryAt(t, &odom_then)) return false;
    *out = compose(correction_, odom_then);
    return true;
  }

  bool odometryAt(double t, Pose2D* out) const {
    if (odom_.empty() || t < odom_.front().t - 0.05) return false;
    if (t >= odom_.back().t) {
      *out = odom_.back().pose;
      return t - odom_.back().t < 0.5;
    }
    for (std::size_t i = 1; i < odom_.size(); ++i) {
      if (odom_[i].t >= t) {
        const auto &a = odom_[i - 1], &b = odom_[i];
        const double k = b.t > a.t ? (t - a.t) / (b.t - a.t) : 1.0;
        *out = {a.pose.x + k * (b.pose.x - a.pose.x), a.pose.y + k * (b.pose.y - a.pose.y),
                wrapAngle(a.pose.theta + k * wrapAngle(b.pose.theta - a.pose.theta))};
        return true;
      }
    }
    *out = odom_.front().pose;
    return true;
  }

  void clear() {
    odom_.clear();
    has_ = false;
  }

 private:
  struct Stamped {
    double t;
    Pose2D pose;
  };
  double history_;
  std::deque<Stamped> odom_;
  Pose2D correction_;
  bool has_ = false, raw_ = false;
};

}  // namespace driver
}  // namespace hal_nodes
