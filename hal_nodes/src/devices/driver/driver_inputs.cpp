// The Driver device (driver.h): its inputs: the pose it steers by, the drive effector's status, path edits and obstacles.
#include "driver.h"

#include <robot_core/command_gate.h>

namespace hal_nodes {

using namespace driver;
using namespace driver_device;

void Driver::updatePose() {
  if (auto o = odom_->newest()) fusion_.addOdometry(o->header.stamp.toSec(), poseOf(o->pose.pose));
  auto m = pose_->newest();
  if (m && m->header.stamp != last_map_stamp_) {
    last_map_stamp_ = m->header.stamp;
    fusion_.setMapPose(m->header.stamp.toSec(), poseOf(m->pose.pose));
  }
}

// The map pose, or false with the result code and reason when localization is not usable.
bool Driver::mapPose(Pose2D* pose, uint8_t* code, std::string* why) {
  const auto m = pose_->fresh(settings_.max_pose_age);
  const auto q = quality_->fresh(settings_.max_pose_age);
  if (!m || !q) {
    *code = LOCALIZATION_STALE;
    char buf[160];
    snprintf(buf, sizeof buf, "localization stale: pose age %.2f s, quality age %.2f s (max %.2f s)", pose_->age(),
             quality_->age(), settings_.max_pose_age);
    *why = buf;
    return false;
  }
  if (q->lost || !(q->probability >= settings_.min_probability)) {
    *code = LOCALIZATION_UNCERTAIN;
    char buf[160];
    snprintf(buf, sizeof buf, "localization uncertain: probability %.2f < %.2f%s", q->probability, settings_.min_probability,
             q->lost ? ", lost" : "");
    *why = buf;
    return false;
  }
  // Carried forward by odometry when odometry is fresh, else the estimate as it is.
  if (const auto o = odom_->fresh(settings_.max_odom_age)) {
    if (fusion_.mapPose(pose)) {
      predictToNow(*o, pose);
      return true;
    }
  }
  *pose = poseOf(m->pose.pose);
  return true;
}

// Carries the odometry pose to now (why: at the declaration in driver.h).
void Driver::predictToNow(const nav_msgs::Odometry& o, Pose2D* pose) const {
  if (!settings_.predict_pose) return;
  const double dt = (ros::Time::now() - o.header.stamp).toSec();
  if (!(dt > 0.0) || dt > settings_.max_odom_age) return;
  const double v = o.twist.twist.linear.x, w = o.twist.twist.angular.z;
  if (!std::isfinite(v) || !std::isfinite(w)) return;
  const double mid = pose->theta + 0.5 * w * dt;
  pose->x += v * dt * std::cos(mid);
  pose->y += v * dt * std::sin(mid);
  pose->theta = wrapAngle(pose->theta + w * dt);
}

bool Driver::odomPose(Pose2D* pose) {
  const auto o = odom_->fresh(settings_.max_odom_age);
  if (!o) return false;
  *pose = poseOf(o->pose.pose);
  return true;
}

void Driver::onDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& msg) {
  for (const auto& s : msg->status) {
    const std::size_t skip = (!s.name.empty() && s.name[0] == '/') ? 1 : 0;  // either naming form
    if (s.name.compare(skip, settings_.motor_status.size(), settings_.motor_status) != 0) continue;
    motor_fault_ = s.level >= diagnostic_msgs::DiagnosticStatus::ERROR;
    motor_fault_message_ = s.name + ": " + s.message;
  }
}

void Driver::onPathEdit(const ros::MessageEvent<PathEdit const>& event) {
  if (!robot_core::CommandGate::instance().accept(event.getPublisherName(), "path_edit")) return;
  const PathEdit::ConstPtr& e = event.getConstMessage();
  if (mode_ != Mode::PATH) {
    ++edits_dropped_;
    ROS_WARN_THROTTLE(1.0, "driver: path edit ignored, no follow_path goal running");
    return;
  }
  pending_edits_.push_back(*e);
}

// Obstacle points in the map from the rangers (via tf) and the tracked opponent.
std::vector<Point2D> Driver::obstacles(const Pose2D& robot) {
  std::vector<Point2D> out;
  for (const auto& r : rangers_) {
    const auto m = r->fresh(settings_.max_obstacle_age);
    if (!m || !std::isfinite(m->range) || m->range <= m->min_range || m->range >= m->max_range) continue;
    Pose2D mount;
    if (!rangerMount(m->header.frame_id, &mount)) continue;
    // Placed from where the robot was when the reading was taken (it may have turned since).
    Pose2D then = robot;
    fusion_.mapPoseAt(m->header.stamp.toSec(), &then);
    const double c = std::cos(then.theta), s = std::sin(then.theta);
    const Pose2D sensor{then.x + c * mount.x - s * mount.y, then.y + s * mount.x + c * mount.y, then.theta + mount.theta};
    // A wide cone sees a border off its axis: such an echo is not the opponent.
    if (avoidance_.borderExplains(sensor, m->field_of_view, m->range)) {
      ++border_echoes_;
      continue;
    }
    const Point2D p{sensor.x + m->range * std::cos(sensor.theta), sensor.y + m->range * std::sin(sensor.theta)};
    if (avoidance_.plausibleObstacle(p)) out.push_back(p);
  }
  if (opponent_) {
    if (const auto o = opponent_->fresh(settings_.max_obstacle_age)) {
      const Point2D p{o->point.x, o->point.y};
      if (avoidance_.plausibleObstacle(p)) out.push_back(p);
    }
  }
  return out;
}

bool Driver::rangerMount(const std::string& frame, Pose2D* mount) {
  auto it = mounts_.find(frame);
  if (it != mounts_.end()) {
    *mount = it->second;
    return true;
  }
  try {
    const auto t = tf_buffer_->lookupTransform(settings_.base_frame, frame, ros::Time(0));
    const Pose2D m{t.transform.translation.x, t.transform.translation.y, yawOf(t.transform.rotation)};
    mounts_[frame] = m;  // mounted rigidly: look it up once
    *mount = m;
    return true;
  } catch (const tf2::TransformException& e) {
    ++tf_errors_;
    ROS_WARN_THROTTLE(2.0, "driver: no transform %s <- %s: %s", settings_.base_frame.c_str(), frame.c_str(), e.what());
    return false;
  }
}

}  // namespace hal_nodes
