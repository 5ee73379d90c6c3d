// The Driver device (driver.h): the goals' lifecycle: accepted, taken over, held through a passing fault, resumed, stalled.
#include "driver.h"

#include <limits>

namespace hal_nodes {

using namespace driver;
using namespace driver_device;

bool Driver::preemptRequested() const {
  switch (mode_) {
    case Mode::GOTO: return goto_from_move_base_ ? move_base_->isPreemptRequested() : goto_->isPreemptRequested();
    case Mode::STRAIGHT: return straight_as_->isPreemptRequested();
    case Mode::ROTATE: return rotate_as_->isPreemptRequested();
    case Mode::PATH: return path_as_->isPreemptRequested();
    case Mode::NONE: break;
  }
  return false;
}

void Driver::acceptNewGoals() {
  if (goto_->isNewGoalAvailable()) {
    if (mode_ == Mode::GOTO && goto_from_move_base_) finish(CANCELED, "preempted by a new goal", false);
    startGoto(*goto_->acceptNewGoal());
  }
  if (move_base_->isNewGoalAvailable()) {
    if (mode_ == Mode::GOTO && !goto_from_move_base_) finish(CANCELED, "preempted by a new goal", false);
    startMoveBase(*move_base_->acceptNewGoal());
  }
  if (straight_as_->isNewGoalAvailable()) startStraight(*straight_as_->acceptNewGoal());
  if (rotate_as_->isNewGoalAvailable()) startRotate(*rotate_as_->acceptNewGoal());
  if (path_as_->isNewGoalAvailable()) startPath(*path_as_->acceptNewGoal());
}

// A goal taking over: the running one of another action is preempted (same action: actionlib did it).
void Driver::takeOver(Mode next) {
  if (mode_ != Mode::NONE && mode_ != next) finish(CANCELED, "preempted by a new goal", false);
  mode_ = next;
  ++goals_;
  avoidance_used_.clear();
  detours_ = 0;
  blocked_since_ = ros::Time();
  stopped_now_ = false;
  held_since_ = ros::Time();
  stall_since_ = ros::Time();
  waiting_.clear();
  move_started_ = false;
  resume_after_recovery_ = false;
  recovery_.reset();
  limiter_.reset();
  stopNow();
}

// Whether the running goal's inputs allow driving now, with the pose to steer by (map for goto
// and follow_path, odometry for relative moves); if not, the code and reason.
bool Driver::inputsSound(Pose2D* pose, uint8_t* code, std::string* why) {
  if (motor_fault_) {
    *code = MOTOR_FAULT;
    *why = "drive effector reports an error: " + motor_fault_message_;
    return false;
  }
  if (mode_ == Mode::STRAIGHT || mode_ == Mode::ROTATE) {
    if (odomPose(pose)) return true;
    *code = ODOMETRY_STALE;
    char buf[96];
    snprintf(buf, sizeof buf, "odometry stale: age %.2f s (max %.2f s)", odom_->age(), settings_.max_odom_age);
    *why = buf;
    return false;
  }
  return mapPose(pose, code, why);
}

// Zero speed while the fault lasts, the feedback saying why; past ~max_hold the goal ends.
void Driver::hold(uint8_t code, const std::string& why, const ros::Time& now) {
  if (held_since_.isZero()) {
    held_since_ = now;
    ++holds_;
    if (settings_.max_hold > 0.0) ROS_WARN("driver: goal held at zero speed: %s", why.c_str());
  }
  if ((now - held_since_).toSec() >= settings_.max_hold) {
    if (settings_.max_hold <= 0.0) return finish(code, why, false);
    char buf[64];
    snprintf(buf, sizeof buf, " (held for longer than max_hold, %.1f s)", settings_.max_hold);
    return finish(code, why + buf, false);
  }
  waiting_ = why;
  stopNow();
  publishFeedback();
}

// The inputs are sound (again, or for the first time since the goal came): a goto or a path
// is planned from where the robot is now (it may have been pushed while it held); a relative
// move keeps its target in the odometry frame and is only started if it was not yet.
void Driver::resume(const Pose2D& pose) {
  if (!held_since_.isZero())
    ROS_INFO("driver: inputs sound again after %.2f s: the goal goes on", (ros::Time::now() - held_since_).toSec());
  held_since_ = ros::Time();
  waiting_.clear();
  limiter_.reset();
  const bool after_recovery = resume_after_recovery_;
  resume_after_recovery_ = false;
  switch (mode_) {
    case Mode::GOTO:
      startLeg(pose);
      break;
    case Mode::PATH:
      if (move_started_) {
        popPassed();
        queue_.erase(queue_.begin(), queue_.begin() + passed_in_path_);
      }
      rebuildPath(pose);
      break;
    case Mode::STRAIGHT:
      if (move_started_ && !after_recovery) break;
      if (move_started_) {  // after a recovery: what is left of the distance, from here
        const double left = straight_.remaining();
        straight_.start(pose, left, straight_goal_.tolerance > 0 ? straight_goal_.tolerance : settings_.default_straight_tolerance,
                        straight_goal_.max_speed);
        break;
      }
      straight_.start(pose, straight_goal_.backwards ? -straight_goal_.distance : straight_goal_.distance,
                      straight_goal_.tolerance > 0 ? straight_goal_.tolerance : settings_.default_straight_tolerance,
                      straight_goal_.max_speed);
      break;
    case Mode::ROTATE:
      if (move_started_ && !after_recovery) break;
      if (move_started_) {  // after a recovery: what is left of the angle, from here
        const double left = rotation_.remaining();
        rotation_.start(pose, left, rotate_goal_.tolerance > 0 ? rotate_goal_.tolerance : settings_.default_angle_tolerance,
                        rotate_goal_.max_speed);
        break;
      }
      rotation_.start(pose, rotate_goal_.angle, rotate_goal_.tolerance > 0 ? rotate_goal_.tolerance : settings_.default_angle_tolerance,
                      rotate_goal_.max_speed);
      break;
    case Mode::NONE:
      return;
  }
  move_started_ = true;
}

// Commanded to move, odometry reads no motion, for stall_timeout: stalled.
bool Driver::stalled(const ros::Time& now) {
  static constexpr double kMoving = 0.05, kTurning = 0.3;     // [m/s, rad/s] commanded
  static constexpr double kStillV = 0.01, kStillW = 0.05;    // [m/s, rad/s] measured
  const Twist2D cmd = limiter_.last();
  const auto o = odom_->fresh(settings_.max_odom_age);
  const bool pushing = settings_.stall_timeout > 0.0 && o && (std::abs(cmd.v) >= kMoving || std::abs(cmd.w) >= kTurning) &&
                       std::abs(o->twist.twist.linear.x) < kStillV && std::abs(o->twist.twist.angular.z) < kStillW;
  if (!pushing) {
    stall_since_ = ros::Time();
    return false;
  }
  if (stall_since_.isZero()) stall_since_ = now;
  if ((now - stall_since_).toSec() < settings_.stall_timeout) return false;
  char buf[160];
  snprintf(buf, sizeof buf, "stalled: commanded v %.2f m/s, w %.2f rad/s but odometry reads no motion for %.1f s", cmd.v, cmd.w,
           (now - stall_since_).toSec());
  stall_message_ = buf;
  ++stalls_;
  return true;
}

// ---------------------------------------------------------------- recoveries
void Driver::onBlocked(const std::string& why) {
  BlockedAt at;
  at.turn_left = turnLeft();
  at.rear_free = rearFree();
  Pose2D odom;
  const bool have_odom = odomPose(&odom);
  at.odom = odom;
  std::vector<std::string> skipped;
  if (have_odom && recovery_.start(at, ros::Time::now().toSec(), &skipped)) {
    ++recoveries_;
    blocked_why_ = why;
    std::string notes;
    for (const auto& s : skipped) notes += "; skipped " + s;
    ROS_WARN("driver: %s: recovery %s%s", why.c_str(), recovery_.describe().c_str(), notes.c_str());
    stall_since_ = blocked_since_ = ros::Time();
    limiter_.reset();
    stopNow();
    publishFeedback();
    return;
  }
  if (recovery_.count() == 0) return finish(BLOCKED, why, false);
  const std::string tried = recovery_.tried();
  std::string notes;
  for (const auto& s : skipped) notes += "; skipped " + s;
  finish(BLOCKED, why + " (recoveries tried: " + (tried.empty() ? std::string("none") : tried) + notes + ")", false);
}

void Driver::stepRecovery(const ros::Time& now, double dt) {
  Pose2D odom;
  if (!odomPose(&odom)) {  // no odometry to move by: stand still until it is back (or max_hold ends it)
    char buf[96];
    snprintf(buf, sizeof buf, "recovery %s: odometry stale (age %.2f s)", recovery_.describe().c_str(), odom_->age());
    return hold(ODOMETRY_STALE, buf, now);
  }
  held_since_ = ros::Time();
  waiting_.clear();
  if (stalled(now)) return onBlocked(blocked_why_ + "; then the recovery stalled too");
  const Twist2D cmd = recovery_.step(odom, limiter_.last(), now.toSec(), rearFree());
  if (!recovery_.running()) {
    ROS_INFO("driver: recovery done: the goal goes on from where the robot is");
    resume_after_recovery_ = true;
    stall_since_ = blocked_since_ = ros::Time();
    stopNow();
    publishFeedback();
    return;
  }
  drive(cmd, dt);
  publishFeedback();
}

double Driver::rearFree() const {
  if (rear_rangers_.empty()) return -1.0;
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& r : rear_rangers_) {
    const auto m = r->fresh(settings_.max_obstacle_age);
    if (!m) return -1.0;
    // Nothing seen: free as far as the ranger sees.
    const double free = std::isfinite(m->range) && m->range < m->max_range ? m->range : m->max_range;
    nearest = std::min(nearest, free);
  }
  return nearest;
}

double Driver::turnLeft() const {
  if (mode_ == Mode::ROTATE) return rotation_.remaining();
  if (mode_ == Mode::GOTO && waypoints_.empty() &&
      (autopilot_.phase() == Autopilot::Phase::TURN || autopilot_.phase() == Autopilot::Phase::ROTATE))
    return autopilot_.headingError();
  return 0.0;
}

void Driver::publishFeedback() {
  switch (mode_) {
    case Mode::GOTO: publishGotoFeedback(); break;
    case Mode::PATH: publishPathFeedback(); break;
    case Mode::STRAIGHT:
    case Mode::ROTATE: publishRelativeFeedback(); break;
    case Mode::NONE: break;
  }
}

bool Driver::refuseIfInactive() {
  if (active()) return false;
  finish(DEACTIVATED, "effectors deactivated: goal refused", false);
  return true;
}

// A goal in the map frame needs localization to have been sound once since this driver
// started: a HAL respawned mid-match resumes from a saved pose, and must not drive on it before
// the filter has confirmed it. Later faults hold a goal instead (hold()).
bool Driver::refuseUntilLocalized() {
  if (localized_once_) return false;
  Pose2D pose;
  uint8_t code;
  std::string why;
  if (!mapPose(&pose, &code, &why)) {
    finish(code, "goal refused until localization is sound: " + why, false);
    return true;
  }
  localized_once_ = true;
  return false;
}

void Driver::startGoto(const GotoGoal& g, bool from_move_base) {
  takeOver(Mode::GOTO);
  goto_from_move_base_ = from_move_base;  // which server a refusal below answers
  if (refuseIfInactive() || refuseUntilLocalized()) return;
  if (!finite({g.x, g.y, g.angle, g.position_tolerance, g.angle_tolerance, g.max_speed, g.timeout}) ||
      g.position_tolerance < 0 || g.angle_tolerance < 0 || g.max_speed < 0 || g.timeout < 0)
    return finish(INVALID_GOAL, "goal fields must be finite and tolerances, max_speed, timeout >= 0", false);
  goal_ = AutopilotGoal();
  goal_.target = {g.x, g.y, g.angle};
  goal_.position_tolerance = g.position_tolerance > 0 ? g.position_tolerance : settings_.default_position_tolerance;
  goal_.angle_tolerance = g.angle_tolerance > 0 ? g.angle_tolerance : settings_.default_angle_tolerance;
  goal_.max_speed = g.max_speed;
  goal_.allow_reverse = g.allow_reverse;
  waypoints_.clear();
  setTimeout(g.timeout);  // refresh() starts the autopilot from the pose it has (resume())
}

void Driver::startStraight(const GoStraightGoal& g) {
  takeOver(Mode::STRAIGHT);
  if (refuseIfInactive()) return;
  if (!finite({g.distance, g.tolerance, g.max_speed, g.timeout}) || g.distance < 0 || g.tolerance < 0 || g.max_speed < 0 ||
      g.timeout < 0)
    return finish(INVALID_GOAL, "distance, tolerance, max_speed, timeout must be finite and >= 0", false);
  straight_goal_ = g;
  setTimeout(g.timeout);  // refresh() starts the move from the odometry it has (resume())
}

void Driver::startRotate(const RotateByGoal& g) {
  takeOver(Mode::ROTATE);
  if (refuseIfInactive()) return;
  if (!finite({g.angle, g.tolerance, g.max_speed, g.timeout}) || g.tolerance < 0 || g.max_speed < 0 || g.timeout < 0)
    return finish(INVALID_GOAL, "angle, tolerance, max_speed, timeout must be finite, the last three >= 0", false);
  rotate_goal_ = g;
  setTimeout(g.timeout);  // refresh() starts the rotation from the odometry it has (resume())
}

void Driver::startPath(const FollowPathGoal& g) {
  takeOver(Mode::PATH);
  if (refuseIfInactive() || refuseUntilLocalized()) return;
  if (g.checkpoints.empty()) return finish(INVALID_GOAL, "no checkpoints", false);
  if (!finite({g.tolerance, g.max_speed, g.timeout}) || g.tolerance < 0 || g.max_speed < 0 || g.timeout < 0)
    return finish(INVALID_GOAL, "tolerance, max_speed, timeout must be finite and >= 0", false);
  queue_.clear();
  for (const auto& c : g.checkpoints) {
    if (!finite({c.x, c.y}) || (c.has_heading && !std::isfinite(c.heading)))
      return finish(INVALID_GOAL, "checkpoint coordinates must be finite", false);
    queue_.push_back(driver::Checkpoint{c.x, c.y, static_cast<bool>(c.has_heading), c.heading});
  }
  path_tolerance_ = g.tolerance > 0 ? g.tolerance : settings_.default_position_tolerance;
  path_max_speed_ = g.max_speed;
  checkpoints_passed_ = 0;
  passed_in_path_ = 0;
  max_cross_track_ = 0.0;
  pending_edits_.clear();
  setTimeout(g.timeout);  // refresh() builds the curve from the pose it has (resume())
}

}  // namespace hal_nodes
