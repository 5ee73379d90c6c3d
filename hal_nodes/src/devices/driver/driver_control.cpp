// The Driver device (driver.h): each goal driven period by period (goto, relative moves, follow_path), avoidance and the end of a goal.
#include "driver.h"

namespace hal_nodes {

using namespace driver;
using namespace driver_device;

void Driver::send(const Twist2D& cmd) {
  geometry_msgs::Twist t;
  t.linear.x = cmd.v;
  t.angular.z = cmd.w;
  cmd_pub_.publish(t);
}

// Zero at once, no ramp: cancel, new goal, abort, deactivation.
void Driver::stopNow() {
  limiter_.reset();
  send(Twist2D());
}

void Driver::drive(const Twist2D& desired, double dt) {
  if (!active()) return stopNow();
  send(limiter_.apply(desired, dt));
}

std::string Driver::avoidanceNow() const {
  if (stopped_now_) return "stopped";
  if (!waypoints_.empty() || detour_active_) return "detour";
  return "none";
}

void Driver::noteAvoidance(const std::string& what) {
  if (avoidance_used_.find(what) != std::string::npos) return;
  avoidance_used_ = avoidance_used_.empty() ? what : avoidance_used_ + "+" + what;
}

bool Driver::blockedTooLong() const {
  return !blocked_since_.isZero() && (ros::Time::now() - blocked_since_).toSec() > avoidance_.config().blocked_timeout;
}

void Driver::stepGoto(const Pose2D& pose, double dt) {
  // The route: robot, detour waypoints, target.
  std::vector<Point2D> route{{pose.x, pose.y}};
  for (const auto& w : waypoints_) route.push_back(w);
  route.push_back({goal_.target.x, goal_.target.y});
  std::vector<Point2D> detour;
  // Only while driving: turning in place sweeps no new ground (and a ranger swinging past a
  // border reads it late); the route is checked again as soon as the robot drives off.
  const bool blocked = autopilot_.phase() == Autopilot::Phase::DRIVE ? avoid(pose, route, {goal_.target.x, goal_.target.y}, &detour)
                                                                     : false;
  if (!detour.empty()) {
    waypoints_.insert(waypoints_.begin(), detour.begin(), detour.end());
    startLeg(pose);
  }
  if (blocked) {
    if (blockedTooLong()) return onBlocked("route blocked by an obstacle for longer than avoidance/blocked_timeout");
    drive(Twist2D(), dt);  // brake at the deceleration limit: braking_distance allows it
    publishGotoFeedback();
    return;
  }
  // Odometry's twist tells the Autopilot when the wheels have really stopped.
  Twist2D measured;
  const Twist2D* measured_ptr = nullptr;
  if (const auto o = odom_->fresh(settings_.max_odom_age)) {
    measured = {o->twist.twist.linear.x, o->twist.twist.angular.z};
    measured_ptr = &measured;
  }
  const Twist2D desired = autopilot_.step(pose, limiter_.last(), measured_ptr);
  if (autopilot_.done()) {
    if (!waypoints_.empty()) {  // a detour waypoint reached: on to the next leg
      waypoints_.erase(waypoints_.begin());
      startLeg(pose);
      drive(autopilot_.step(pose, limiter_.last()), dt);
      publishGotoFeedback();
      return;
    }
    send(Twist2D());
    return finish(REACHED, "reached", true);
  }
  drive(desired, dt);
  publishGotoFeedback();
}

// Aim the autopilot at the next waypoint (passing through, no stop) or the goal itself.
void Driver::startLeg(const Pose2D& pose) {
  detour_active_ = !waypoints_.empty();
  if (waypoints_.empty()) {
    autopilot_.start(goal_, pose);
    return;
  }
  AutopilotGoal leg = goal_;
  leg.target = {waypoints_.front().x, waypoints_.front().y, 0.0};
  leg.position_tolerance = settings_.detour_tolerance;
  leg.final_heading = false;
  leg.allow_reverse = false;
  autopilot_.start(leg, pose);
}

void Driver::publishGotoFeedback() {
  GotoFeedback f;
  Pose2D pose;
  fusion_.mapPose(&pose);
  f.distance_remaining = std::hypot(goal_.target.x - pose.x, goal_.target.y - pose.y);
  f.progress = waypoints_.empty() && !detour_active_ ? autopilot_.progressPercent() : 0.0;
  f.phase = waiting_.empty() ? Autopilot::phaseName(autopilot_.phase()) : "holding";
  f.avoidance = avoidanceNow();
  f.waiting = waiting_;
  f.recovery = recovery_.describe();
  if (goto_from_move_base_) publishMoveBaseFeedback(pose);
  else goto_->publishFeedback(f);
}

void Driver::stepRelative(const Pose2D& pose, double dt) {
  if (mode_ == Mode::STRAIGHT) {
    const Twist2D d = straight_.step(pose, limiter_.last());
    if (straight_.done()) return finish(REACHED, "reached", true);
    drive(d, dt);
  } else {
    const Twist2D d = rotation_.step(pose, limiter_.last());
    if (rotation_.done()) return finish(REACHED, "reached", true);
    drive(d, dt);
  }
  publishRelativeFeedback();
}

void Driver::publishRelativeFeedback() {
  if (mode_ == Mode::STRAIGHT) {
    GoStraightFeedback f;
    if (move_started_) {
      f.distance_remaining = straight_.remaining();
      f.progress = straight_.progressPercent();
    }
    f.waiting = waiting_;
    f.recovery = recovery_.describe();
    straight_as_->publishFeedback(f);
  } else if (mode_ == Mode::ROTATE) {
    RotateByFeedback f;
    if (move_started_) {
      f.angle_remaining = rotation_.remaining();
      f.progress = rotation_.progressPercent();
    }
    f.waiting = waiting_;
    f.recovery = recovery_.describe();
    rotate_as_->publishFeedback(f);
  }
}

void Driver::rebuildPath(const Pose2D& pose) {
  const HermitePath path(pose, queue_);
  follower_.start(path.sample(path_config_.sample_step), path_tolerance_, path_max_speed_);
  passed_in_path_ = 0;
  nav_msgs::Path msg;
  msg.header.stamp = ros::Time::now();
  msg.header.frame_id = settings_.map_frame;
  const auto& samples = follower_.samples();
  for (std::size_t i = 0; i < samples.size(); i = (i + 4 < samples.size() || i + 1 == samples.size()) ? i + 4 : samples.size() - 1) {
    geometry_msgs::PoseStamped ps;
    ps.header = msg.header;
    ps.pose.position.x = samples[i].x;
    ps.pose.position.y = samples[i].y;
    ps.pose.orientation.z = std::sin(samples[i].heading / 2.0);
    ps.pose.orientation.w = std::cos(samples[i].heading / 2.0);
    msg.poses.push_back(ps);  // every 4th sample and the last one
  }
  path_pub_.publish(msg);
}

// Drop the checkpoints the follower has passed from the queue.
void Driver::popPassed() {
  const int passed = std::min<int>(follower_.segment(), static_cast<int>(queue_.size()));
  if (passed > passed_in_path_) {
    checkpoints_passed_ += passed - passed_in_path_;
    passed_in_path_ = passed;
  }
}

void Driver::applyEdits(const Pose2D& pose) {
  if (pending_edits_.empty()) return;
  popPassed();
  queue_.erase(queue_.begin(), queue_.begin() + passed_in_path_);
  for (const auto& e : pending_edits_) {
    const driver::Checkpoint c{e.checkpoint.x, e.checkpoint.y, static_cast<bool>(e.checkpoint.has_heading), e.checkpoint.heading};
    const bool ok_point = finite({c.x, c.y}) && (!c.has_heading || std::isfinite(c.heading));
    const std::size_t i = e.index;
    bool applied = false;
    switch (e.op) {
      case PathEdit::APPEND:
        if ((applied = ok_point)) queue_.push_back(c);
        break;
      case PathEdit::INSERT:
        if ((applied = ok_point && i <= queue_.size())) queue_.insert(queue_.begin() + i, c);
        break;
      case PathEdit::REMOVE:
        if ((applied = i < queue_.size() && queue_.size() > 1)) queue_.erase(queue_.begin() + i);
        break;
      case PathEdit::REPLACE:
        if ((applied = ok_point && i < queue_.size())) queue_[i] = c;
        break;
      default:
        break;
    }
    if (!applied) {
      ++edits_dropped_;
      ROS_WARN("driver: path edit op %u index %zu refused (%zu checkpoints ahead)", e.op, i, queue_.size());
    }
  }
  pending_edits_.clear();
  rebuildPath(pose);
}

void Driver::stepPath(const Pose2D& pose, double dt) {
  applyEdits(pose);
  const auto& samples = follower_.samples();
  std::vector<Point2D> route{{pose.x, pose.y}};
  for (std::size_t i = follower_.index(); i < samples.size(); i += 4) route.push_back({samples[i].x, samples[i].y});
  route.push_back({samples.back().x, samples.back().y});
  std::vector<Point2D> detour;
  const bool blocked = avoid(pose, route, route.back(), &detour);
  if (!detour.empty()) {
    popPassed();
    queue_.erase(queue_.begin(), queue_.begin() + passed_in_path_);
    queue_.insert(queue_.begin(), {driver::Checkpoint{detour[0].x, detour[0].y}, driver::Checkpoint{detour[1].x, detour[1].y}});
    rebuildPath(pose);
  }
  if (blocked) {
    if (blockedTooLong()) return onBlocked("route blocked by an obstacle for longer than avoidance/blocked_timeout");
    drive(Twist2D(), dt);
  } else {
    const Twist2D desired = follower_.step(pose, limiter_.last());
    max_cross_track_ = std::max(max_cross_track_, follower_.crossTrackError());
    popPassed();
    if (follower_.done()) {
      send(Twist2D());
      return finish(REACHED, "reached", true);
    }
    drive(desired, dt);
  }
  publishPathFeedback();
}

void Driver::publishPathFeedback() {
  FollowPathFeedback f;
  f.waiting = waiting_;
  if (!move_started_) return path_as_->publishFeedback(f);  // no curve yet: only why it waits
  f.distance_remaining = follower_.remaining();
  f.progress = follower_.progressPercent();
  f.checkpoints_passed = checkpoints_passed_;
  f.checkpoints_remaining = static_cast<uint32_t>(std::max(0, static_cast<int>(queue_.size()) - passed_in_path_));
  f.cross_track_error = follower_.crossTrackError();
  f.avoidance = avoidanceNow();
  f.waiting = waiting_;
  f.recovery = recovery_.describe();
  path_as_->publishFeedback(f);
}

// End the running goal: stop the wheels and report. `success` only with REACHED.
void Driver::finish(uint8_t code, const std::string& message, bool success) {
  const Mode mode = mode_;
  mode_ = Mode::NONE;
  timeout_ = ros::Time();
  held_since_ = ros::Time();
  waiting_.clear();
  detour_active_ = false;
  stopped_now_ = false;
  stopNow();
  if (!success) {
    ++aborted_;
    if (code != CANCELED) ROS_WARN("driver: goal ended: %s", message.c_str());
  }
  auto end = [&](auto& server, auto result) {
    result.code = code;
    result.message = message;
    if (success) server.setSucceeded(result, message);
    else if (!server.isActive()) return;
    else if (code == CANCELED) server.setPreempted(result, message);
    else server.setAborted(result, message);
  };
  Pose2D pose;
  const bool has_pose = fusion_.mapPose(&pose);
  switch (mode) {
    case Mode::GOTO: {
      GotoResult r;
      if (has_pose) {
        r.position_error = std::hypot(goal_.target.x - pose.x, goal_.target.y - pose.y);
        r.angle_error = wrapAngle(goal_.target.theta - pose.theta);
      }
      r.avoidance = avoidanceSummary();
      r.detours = detours_;
      if (goto_from_move_base_) endMoveBase(code, message, success);
      else end(*goto_, r);
      break;
    }
    case Mode::STRAIGHT: {
      GoStraightResult r;
      r.distance_error = straight_.remaining();
      end(*straight_as_, r);
      break;
    }
    case Mode::ROTATE: {
      RotateByResult r;
      r.angle_error = rotation_.remaining();
      end(*rotate_as_, r);
      break;
    }
    case Mode::PATH: {
      FollowPathResult r;
      r.checkpoints_passed = checkpoints_passed_;
      if (has_pose && !queue_.empty()) r.position_error = std::hypot(queue_.back().x - pose.x, queue_.back().y - pose.y);
      r.max_cross_track_error = max_cross_track_;
      r.avoidance = avoidanceSummary();
      r.detours = detours_;
      end(*path_as_, r);
      break;
    }
    case Mode::NONE:
      break;
  }
}

}  // namespace hal_nodes
