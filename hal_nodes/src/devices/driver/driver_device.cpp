// Driver: moves a differential-drive robot, as four preemptible actions under ~ (/hal/driver):
//   goto         absolute pose in the map: the Autopilot (driver/autopilot.h)
//   go_straight  distance along the heading, from odometry alone (driver/relative_moves.h)
//   rotate_by    relative angle, from odometry alone
//   follow_path  checkpoints joined by cubic Hermite segments (driver/hermite_path.h,
//                driver/path_follower.h); ~path_edit (hal_nodes/PathEdit) changes the
//                checkpoints ahead while it runs; the curve is published on ~path (nav_msgs/Path)
// It commands geometry_msgs/Twist on ~cmd_vel_topic (/hal/drive/cmd_vel) only while a goal
// runs; refresh() at ~rate is the control loop. One goal at a time: a goal on any action
// preempts the running one.
//
// Safety. These end the goal at once, wheels stopped, with a result code saying why: cancel /
// new goal (zero published at once, in the callback), /effectors/deactivate (this is an
// Effector), the goal's own timeout.
// A passing fault holds the goal instead: the wheels stop at once, the feedback's `waiting`
// says why, and the goal resumes from where the robot is when the inputs are sound again; only
// a fault lasting longer than ~max_hold [s] (default 5; 0: end at once) ends the goal with its
// code. The faults: localization older than ~max_pose_age, below ~min_probability or lost
// (goto, follow_path); odometry older than ~max_odom_age (go_straight, rotate_by); the drive
// effector's /diagnostics status at ERROR (~motor_status, a status-name prefix, default
// "hal/drive:"; "" disables). A match is lost by a robot that gives up on a 1 s board outage.
// (~predict_pose [true]: the map pose is carried from the newest /odom's stamp to now by its twist.)
// A stall ends the goal BLOCKED: the wheels commanded (>= 0.05 m/s or 0.3 rad/s) while odometry
// reads no motion for ~stall_timeout [s] (default 1; 0 disables), e.g. pushing a border where no
// ranger or bumper sees it. A motor held at stall heats up and the goal makes no progress.
// Every controlled command goes through the VelocityLimiter (~limits/*); only the stop itself
// skips the deceleration ramp.
//
// Avoidance (~avoidance/*): obstacle points from the rangers (~avoidance/rangers: names on
// ~avoidance/ranger_prefix, placed with tf from base_link; an echo matching the table border
// anywhere in the ranger's field_of_view, within ~avoidance/border_echo_tolerance, is dropped) and an optional tracked opponent
// (~avoidance/opponent_topic, geometry_msgs/PointStamped in map). Mode `stop` brakes within
// ~avoidance/braking_distance and waits up to ~avoidance/blocked_timeout; `detour` inserts two
// waypoints beside the obstacle and continues. Feedback and result say which.
//
// All callbacks (timer, action servers, subscriptions) run on the nodelet's single-threaded
// queue, and refresh()/deactivate() are serialized by the framework; the action callbacks only
// stop the wheels and raise flags, the goal itself is taken over in refresh().
#include <actionlib/server/simple_action_server.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/PointStamped.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/Twist.h>
#include <hal_nodes/FollowPathAction.h>
#include <hal_nodes/GoStraightAction.h>
#include <hal_nodes/GotoAction.h>
#include <hal_nodes/LocalizationQuality.h>
#include <hal_nodes/PathEdit.h>
#include <hal_nodes/RotateByAction.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <sensor_msgs/Range.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>

#include "hal_nodes/device_nodelet.h"
#include "hal_nodes/driver/autopilot.h"
#include "hal_nodes/driver/avoidance.h"
#include "hal_nodes/driver/driver_config.h"
#include "hal_nodes/driver/hermite_path.h"
#include "hal_nodes/driver/path_follower.h"
#include "hal_nodes/driver/pose_fusion.h"
#include "hal_nodes/driver/relative_moves.h"

namespace hal_nodes {

using namespace driver;

namespace {

// Result codes shared by the four actions (same values in every .action file).
enum Code : uint8_t {
  REACHED = 0,
  CANCELED = 1,
  LOCALIZATION_STALE = 2,
  LOCALIZATION_UNCERTAIN = 3,
  MOTOR_FAULT = 4,
  BLOCKED = 5,
  DEACTIVATED = 6,
  INVALID_GOAL = 7,
  ODOMETRY_STALE = 8,
  TIMEOUT = 9,
};

using robot_core::yawOf;

Pose2D poseOf(const geometry_msgs::Pose& p) { return {p.position.x, p.position.y, yawOf(p.orientation)}; }

bool finite(std::initializer_list<double> xs) {
  for (double x : xs)
    if (!std::isfinite(x)) return false;
  return true;
}

}  // namespace

class Driver : public Effector {
 public:
  enum class Mode { NONE, GOTO, STRAIGHT, ROTATE, PATH };

  Driver() : autopilot_(AutopilotConfig()), straight_(AutopilotConfig()), rotation_(AutopilotConfig()),
             follower_(AutopilotConfig(), PathFollowerConfig()), avoidance_(AvoidanceConfig()), limiter_(MotionLimits()) {}

  void init(DeviceContext& ctx) override {
    ros::NodeHandle& p = ctx.pnh;
    period_ = 1.0 / ctx.rate;
    const robot_core::Params params = robot_core::Params::of(p);  // the reader the bench and tests use too
    const AutopilotConfig ap = readAutopilotConfig(params);
    const PathFollowerConfig pf = readPathFollowerConfig(params);
    AvoidanceConfig av = readAvoidanceConfig(params, ap);
    av.table_length = optionalDouble(ctx.nh, "/table/length", av.table_length);
    av.table_width = optionalDouble(ctx.nh, "/table/width", av.table_width);
    params["avoidance"].check("", av.invalidReason());
    ros::NodeHandle pa(p, "avoidance");
    detour_tolerance_ = optionalDouble(pa, "detour_tolerance", 0.05);
    requirePositive(pa, "detour_tolerance", detour_tolerance_);
    obstacle_max_age_ = optionalDouble(pa, "max_obstacle_age", 0.3);
    requirePositive(pa, "max_obstacle_age", obstacle_max_age_);

    default_position_tolerance_ = optionalDouble(p, "default_position_tolerance", 0.01);
    requirePositive(p, "default_position_tolerance", default_position_tolerance_);
    default_angle_tolerance_ = optionalDouble(p, "default_angle_tolerance", 0.035);
    requirePositive(p, "default_angle_tolerance", default_angle_tolerance_);
    default_straight_tolerance_ = optionalDouble(p, "default_straight_tolerance", 0.005);
    requirePositive(p, "default_straight_tolerance", default_straight_tolerance_);
    max_pose_age_ = optionalDouble(p, "max_pose_age", 0.5);
    requirePositive(p, "max_pose_age", max_pose_age_);
    max_odom_age_ = optionalDouble(p, "max_odom_age", 0.2);
    requirePositive(p, "max_odom_age", max_odom_age_);
    stall_timeout_ = optionalDouble(p, "stall_timeout", 1.0);
    requireInRange(p, "stall_timeout", stall_timeout_, 0.0, 60.0);
    max_hold_ = optionalDouble(p, "max_hold", 5.0);
    requireInRange(p, "max_hold", max_hold_, 0.0, 60.0);
    p.param("predict_pose", predict_pose_, true);
    min_probability_ = optionalDouble(p, "min_probability", 0.5);
    requireInRange(p, "min_probability", min_probability_, 0.0, 1.0);
    motor_status_ = optionalString(p, "motor_status", "hal/drive:");
    // diagnostic_updater names a status "<node name without its leading slash>: <task>".
    if (!motor_status_.empty() && motor_status_[0] == '/') motor_status_.erase(0, 1);
    base_frame_ = optionalString(p, "base_frame", "base_link");
    map_frame_ = optionalString(p, "map_frame", "map");

    config_ = ap;
    autopilot_ = Autopilot(ap);
    straight_ = StraightMove(ap);
    rotation_ = Rotation(ap);
    path_config_ = pf;
    follower_ = PathFollower(ap, pf);
    avoidance_ = Avoidance(av);
    limiter_ = VelocityLimiter(ap.limits);

    pose_ = addInput<geometry_msgs::PoseWithCovarianceStamped>(ctx.nh, optionalString(p, "pose_topic", "/mcl/pose"), "pose");
    quality_ = addInput<LocalizationQuality>(ctx.nh, optionalString(p, "quality_topic", "/mcl/quality"), "quality");
    odom_ = addInput<nav_msgs::Odometry>(ctx.nh, optionalString(p, "odom_topic", "/odom"), "odometry");
    if (av.mode != AvoidanceConfig::Mode::OFF) {
      const std::string prefix = optionalString(pa, "ranger_prefix", "/hal/rangers/");
      std::vector<std::string> names;
      if (pa.hasParam("rangers") && !pa.getParam("rangers", names))
        throw ParameterError("parameter " + qualified(pa, "rangers") + ": must be a list of ranger names");
      for (const auto& n : names) rangers_.push_back(addInput<sensor_msgs::Range>(ctx.nh, prefix + n, "ranger " + n));
      const std::string opponent = optionalString(pa, "opponent_topic", "");
      if (!opponent.empty()) opponent_ = addInput<geometry_msgs::PointStamped>(ctx.nh, opponent, "opponent");
      if (!rangers_.empty()) {
        tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
        tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, ctx.nh);
      }
    }

    cmd_pub_ = ctx.nh.advertise<geometry_msgs::Twist>(optionalString(p, "cmd_vel_topic", "/hal/drive/cmd_vel"), 1);
    path_pub_ = p.advertise<nav_msgs::Path>("path", 1, true);
    edit_sub_ = p.subscribe("path_edit", 20, &Driver::onPathEdit, this);
    if (!motor_status_.empty()) diag_sub_ = ctx.nh.subscribe("/diagnostics", 20, &Driver::onDiagnostics, this);

    goto_ = std::make_unique<actionlib::SimpleActionServer<GotoAction>>(p, "goto", false);
    straight_as_ = std::make_unique<actionlib::SimpleActionServer<GoStraightAction>>(p, "go_straight", false);
    rotate_as_ = std::make_unique<actionlib::SimpleActionServer<RotateByAction>>(p, "rotate_by", false);
    path_as_ = std::make_unique<actionlib::SimpleActionServer<FollowPathAction>>(p, "follow_path", false);
    // Callbacks stop the wheels at once; refresh() takes the new goal over at the next period.
    auto stop = [this]() { stopNow(); };
    goto_->registerGoalCallback(stop);
    goto_->registerPreemptCallback(stop);
    straight_as_->registerGoalCallback(stop);
    straight_as_->registerPreemptCallback(stop);
    rotate_as_->registerGoalCallback(stop);
    rotate_as_->registerPreemptCallback(stop);
    path_as_->registerGoalCallback(stop);
    path_as_->registerPreemptCallback(stop);
    goto_->start();
    straight_as_->start();
    rotate_as_->start();
    path_as_->start();
  }

  void refresh() override {
    const ros::Time now = ros::Time::now();
    double dt = last_refresh_.isZero() ? period_ : (now - last_refresh_).toSec();
    last_refresh_ = now;
    dt = std::clamp(dt, 0.0, 3.0 * period_);
    updatePose();
    setAvailable();

    acceptNewGoals();
    if (mode_ != Mode::NONE && preemptRequested()) finish(CANCELED, "canceled", false);
    if (mode_ == Mode::NONE) return;
    if (!timeout_.isZero() && now > timeout_) {
      finish(TIMEOUT, "goal timeout expired", false);
      return;
    }
    Pose2D pose;  // in map (goto, follow_path) or odom (relative moves): read once per period
    uint8_t code;
    std::string why;
    if (!inputsSound(&pose, &code, &why)) return hold(code, why, now);
    if (!held_since_.isZero() || !move_started_) resume(pose);
    if (stalled(now)) return finish(BLOCKED, stall_message_, false);
    switch (mode_) {
      case Mode::GOTO: stepGoto(pose, dt); break;
      case Mode::PATH: stepPath(pose, dt); break;
      case Mode::STRAIGHT:
      case Mode::ROTATE: stepRelative(pose, dt); break;
      case Mode::NONE: break;
    }
  }

  void deactivate() override {
    if (mode_ != Mode::NONE) finish(DEACTIVATED, "effectors deactivated", false);
    stopNow();
  }

  void halt() override {
    if (mode_ != Mode::NONE) finish(CANCELED, "driver shutting down", false);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    static const char* names[] = {"idle", "goto", "go_straight", "rotate_by", "follow_path"};
    stat.add("goal", names[static_cast<int>(mode_)]);
    stat.add("goals accepted", goals_);
    stat.add("goals aborted", aborted_);
    stat.add("path edits dropped", edits_dropped_);
    stat.add("ranger tf errors", tf_errors_);
    stat.add("ranger echoes explained by the border", border_echoes_);
    stat.add("avoidance", avoidanceNow());
    stat.add("motor fault", motor_fault_ ? motor_fault_message_ : std::string("no"));
    stat.add("holding", held_since_.isZero() ? std::string("no") : waiting_);
    stat.add("goals held", holds_);
    stat.add("stalls", stalls_);
    stat.addf("last command", "v %.3f m/s, w %.3f rad/s", limiter_.last().v, limiter_.last().w);
  }

 private:
  // ---------------------------------------------------------------- inputs
  void updatePose() {
    if (auto o = odom_->newest()) fusion_.addOdometry(o->header.stamp.toSec(), poseOf(o->pose.pose));
    auto m = pose_->newest();
    if (m && m->header.stamp != last_map_stamp_) {
      last_map_stamp_ = m->header.stamp;
      fusion_.setMapPose(m->header.stamp.toSec(), poseOf(m->pose.pose));
    }
  }

  // The map pose, or false with the result code and reason when localization is not usable.
  bool mapPose(Pose2D* pose, uint8_t* code, std::string* why) {
    const auto m = pose_->fresh(max_pose_age_);
    const auto q = quality_->fresh(max_pose_age_);
    if (!m || !q) {
      *code = LOCALIZATION_STALE;
      char buf[160];
      snprintf(buf, sizeof buf, "localization stale: pose age %.2f s, quality age %.2f s (max %.2f s)", pose_->age(),
               quality_->age(), max_pose_age_);
      *why = buf;
      return false;
    }
    if (q->lost || !(q->probability >= min_probability_)) {
      *code = LOCALIZATION_UNCERTAIN;
      char buf[160];
      snprintf(buf, sizeof buf, "localization uncertain: probability %.2f < %.2f%s", q->probability, min_probability_,
               q->lost ? ", lost" : "");
      *why = buf;
      return false;
    }
    // Carried forward by odometry when odometry is fresh, else the estimate as it is.
    if (const auto o = odom_->fresh(max_odom_age_)) {
      if (fusion_.mapPose(pose)) {
        predictToNow(*o, pose);
        return true;
      }
    }
    *pose = poseOf(m->pose.pose);
    return true;
  }

  // The newest /odom is already some tens of ms old when a step runs (more on a loaded machine:
  // p99 40-110 ms at load 10-14 in the simulator); at 0.2 m/s on arrival that lag alone made the
  // robot overshoot the goal by 20+ mm. With ~predict_pose, the pose is carried from the odometry
  // stamp to now with the odometry's own twist (bounded by ~max_odom_age via fresh()).
  void predictToNow(const nav_msgs::Odometry& o, Pose2D* pose) const {
    if (!predict_pose_) return;
    const double dt = (ros::Time::now() - o.header.stamp).toSec();
    if (!(dt > 0.0) || dt > max_odom_age_) return;
    const double v = o.twist.twist.linear.x, w = o.twist.twist.angular.z;
    if (!std::isfinite(v) || !std::isfinite(w)) return;
    const double mid = pose->theta + 0.5 * w * dt;
    pose->x += v * dt * std::cos(mid);
    pose->y += v * dt * std::sin(mid);
    pose->theta = wrapAngle(pose->theta + w * dt);
  }

  bool odomPose(Pose2D* pose) {
    const auto o = odom_->fresh(max_odom_age_);
    if (!o) return false;
    *pose = poseOf(o->pose.pose);
    return true;
  }

  void onDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& msg) {
    for (const auto& s : msg->status) {
      const std::size_t skip = (!s.name.empty() && s.name[0] == '/') ? 1 : 0;  // either naming form
      if (s.name.compare(skip, motor_status_.size(), motor_status_) != 0) continue;
      motor_fault_ = s.level >= diagnostic_msgs::DiagnosticStatus::ERROR;
      motor_fault_message_ = s.name + ": " + s.message;
    }
  }

  void onPathEdit(const PathEdit::ConstPtr& e) {
    if (mode_ != Mode::PATH) {
      ++edits_dropped_;
      ROS_WARN_THROTTLE(1.0, "driver: path edit ignored, no follow_path goal running");
      return;
    }
    pending_edits_.push_back(*e);
  }

  // Obstacle points in the map from the rangers (via tf) and the tracked opponent.
  std::vector<Point2D> obstacles(const Pose2D& robot) {
    std::vector<Point2D> out;
    for (const auto& r : rangers_) {
      const auto m = r->fresh(obstacle_max_age_);
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
      if (const auto o = opponent_->fresh(obstacle_max_age_)) {
        const Point2D p{o->point.x, o->point.y};
        if (avoidance_.plausibleObstacle(p)) out.push_back(p);
      }
    }
    return out;
  }

  bool rangerMount(const std::string& frame, Pose2D* mount) {
    auto it = mounts_.find(frame);
    if (it != mounts_.end()) {
      *mount = it->second;
      return true;
    }
    try {
      const auto t = tf_buffer_->lookupTransform(base_frame_, frame, ros::Time(0));
      const Pose2D m{t.transform.translation.x, t.transform.translation.y, yawOf(t.transform.rotation)};
      mounts_[frame] = m;  // mounted rigidly: look it up once
      *mount = m;
      return true;
    } catch (const tf2::TransformException& e) {
      ++tf_errors_;
      ROS_WARN_THROTTLE(2.0, "driver: no transform %s <- %s: %s", base_frame_.c_str(), frame.c_str(), e.what());
      return false;
    }
  }

  // ---------------------------------------------------------------- goals
  bool preemptRequested() const {
    switch (mode_) {
      case Mode::GOTO: return goto_->isPreemptRequested();
      case Mode::STRAIGHT: return straight_as_->isPreemptRequested();
      case Mode::ROTATE: return rotate_as_->isPreemptRequested();
      case Mode::PATH: return path_as_->isPreemptRequested();
      case Mode::NONE: break;
    }
    return false;
  }

  void acceptNewGoals() {
    if (goto_->isNewGoalAvailable()) startGoto(*goto_->acceptNewGoal());
    if (straight_as_->isNewGoalAvailable()) startStraight(*straight_as_->acceptNewGoal());
    if (rotate_as_->isNewGoalAvailable()) startRotate(*rotate_as_->acceptNewGoal());
    if (path_as_->isNewGoalAvailable()) startPath(*path_as_->acceptNewGoal());
  }

  // A goal taking over: the running one of another action is preempted (same action: actionlib did it).
  void takeOver(Mode next) {
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
    limiter_.reset();
    stopNow();
  }

  // ---------------------------------------------------------------- passing faults
  // Whether the running goal's inputs allow driving now, with the pose to steer by (map for goto
  // and follow_path, odometry for relative moves); if not, the code and reason.
  bool inputsSound(Pose2D* pose, uint8_t* code, std::string* why) {
    if (motor_fault_) {
      *code = MOTOR_FAULT;
      *why = "drive effector reports an error: " + motor_fault_message_;
      return false;
    }
    if (mode_ == Mode::STRAIGHT || mode_ == Mode::ROTATE) {
      if (odomPose(pose)) return true;
      *code = ODOMETRY_STALE;
      char buf[96];
      snprintf(buf, sizeof buf, "odometry stale: age %.2f s (max %.2f s)", odom_->age(), max_odom_age_);
      *why = buf;
      return false;
    }
    return mapPose(pose, code, why);
  }

  // Zero speed while the fault lasts, the feedback saying why; past ~max_hold the goal ends.
  void hold(uint8_t code, const std::string& why, const ros::Time& now) {
    if (held_since_.isZero()) {
      held_since_ = now;
      ++holds_;
      if (max_hold_ > 0.0) ROS_WARN("driver: goal held at zero speed: %s", why.c_str());
    }
    if ((now - held_since_).toSec() >= max_hold_) {
      if (max_hold_ <= 0.0) return finish(code, why, false);
      char buf[64];
      snprintf(buf, sizeof buf, " (held for longer than max_hold, %.1f s)", max_hold_);
      return finish(code, why + buf, false);
    }
    waiting_ = why;
    stopNow();
    publishFeedback();
  }

  // The inputs are sound (again, or for the first time since the goal came): a goto or a path
  // is planned from where the robot is now (it may have been pushed while it held); a relative
  // move keeps its target in the odometry frame and is only started if it was not yet.
  void resume(const Pose2D& pose) {
    if (!held_since_.isZero())
      ROS_INFO("driver: inputs sound again after %.2f s: the goal goes on", (ros::Time::now() - held_since_).toSec());
    held_since_ = ros::Time();
    waiting_.clear();
    limiter_.reset();
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
        if (move_started_) break;
        straight_.start(pose, straight_goal_.backwards ? -straight_goal_.distance : straight_goal_.distance,
                        straight_goal_.tolerance > 0 ? straight_goal_.tolerance : default_straight_tolerance_,
                        straight_goal_.max_speed);
        break;
      case Mode::ROTATE:
        if (move_started_) break;
        rotation_.start(pose, rotate_goal_.angle, rotate_goal_.tolerance > 0 ? rotate_goal_.tolerance : default_angle_tolerance_,
                        rotate_goal_.max_speed);
        break;
      case Mode::NONE:
        return;
    }
    move_started_ = true;
  }

  // Commanded to move, odometry reads no motion, for stall_timeout: stalled.
  bool stalled(const ros::Time& now) {
    static constexpr double kMoving = 0.05, kTurning = 0.3;     // [m/s, rad/s] commanded
    static constexpr double kStillV = 0.01, kStillW = 0.05;    // [m/s, rad/s] measured
    const Twist2D cmd = limiter_.last();
    const auto o = odom_->fresh(max_odom_age_);
    const bool pushing = stall_timeout_ > 0.0 && o && (std::abs(cmd.v) >= kMoving || std::abs(cmd.w) >= kTurning) &&
                         std::abs(o->twist.twist.linear.x) < kStillV && std::abs(o->twist.twist.angular.z) < kStillW;
    if (!pushing) {
      stall_since_ = ros::Time();
      return false;
    }
    if (stall_since_.isZero()) stall_since_ = now;
    if ((now - stall_since_).toSec() < stall_timeout_) return false;
    char buf[160];
    snprintf(buf, sizeof buf, "stalled: commanded v %.2f m/s, w %.2f rad/s but odometry reads no motion for %.1f s", cmd.v, cmd.w,
             (now - stall_since_).toSec());
    stall_message_ = buf;
    ++stalls_;
    return true;
  }

  void publishFeedback() {
    switch (mode_) {
      case Mode::GOTO: publishGotoFeedback(); break;
      case Mode::PATH: publishPathFeedback(); break;
      case Mode::STRAIGHT:
      case Mode::ROTATE: publishRelativeFeedback(); break;
      case Mode::NONE: break;
    }
  }

  void setTimeout(double t) { timeout_ = t > 0.0 ? ros::Time::now() + ros::Duration(t) : ros::Time(); }

  bool refuseIfInactive() {
    if (active()) return false;
    finish(DEACTIVATED, "effectors deactivated: goal refused", false);
    return true;
  }

  void startGoto(const GotoGoal& g) {
    takeOver(Mode::GOTO);
    if (refuseIfInactive()) return;
    if (!finite({g.x, g.y, g.angle, g.position_tolerance, g.angle_tolerance, g.max_speed, g.timeout}) ||
        g.position_tolerance < 0 || g.angle_tolerance < 0 || g.max_speed < 0 || g.timeout < 0)
      return finish(INVALID_GOAL, "goal fields must be finite and tolerances, max_speed, timeout >= 0", false);
    goal_ = AutopilotGoal();
    goal_.target = {g.x, g.y, g.angle};
    goal_.position_tolerance = g.position_tolerance > 0 ? g.position_tolerance : default_position_tolerance_;
    goal_.angle_tolerance = g.angle_tolerance > 0 ? g.angle_tolerance : default_angle_tolerance_;
    goal_.max_speed = g.max_speed;
    goal_.allow_reverse = g.allow_reverse;
    waypoints_.clear();
    setTimeout(g.timeout);  // refresh() starts the autopilot from the pose it has (resume())
  }

  void startStraight(const GoStraightGoal& g) {
    takeOver(Mode::STRAIGHT);
    if (refuseIfInactive()) return;
    if (!finite({g.distance, g.tolerance, g.max_speed, g.timeout}) || g.distance < 0 || g.tolerance < 0 || g.max_speed < 0 ||
        g.timeout < 0)
      return finish(INVALID_GOAL, "distance, tolerance, max_speed, timeout must be finite and >= 0", false);
    straight_goal_ = g;
    setTimeout(g.timeout);  // refresh() starts the move from the odometry it has (resume())
  }

  void startRotate(const RotateByGoal& g) {
    takeOver(Mode::ROTATE);
    if (refuseIfInactive()) return;
    if (!finite({g.angle, g.tolerance, g.max_speed, g.timeout}) || g.tolerance < 0 || g.max_speed < 0 || g.timeout < 0)
      return finish(INVALID_GOAL, "angle, tolerance, max_speed, timeout must be finite, the last three >= 0", false);
    rotate_goal_ = g;
    setTimeout(g.timeout);  // refresh() starts the rotation from the odometry it has (resume())
  }

  void startPath(const FollowPathGoal& g) {
    takeOver(Mode::PATH);
    if (refuseIfInactive()) return;
    if (g.checkpoints.empty()) return finish(INVALID_GOAL, "no checkpoints", false);
    if (!finite({g.tolerance, g.max_speed, g.timeout}) || g.tolerance < 0 || g.max_speed < 0 || g.timeout < 0)
      return finish(INVALID_GOAL, "tolerance, max_speed, timeout must be finite and >= 0", false);
    queue_.clear();
    for (const auto& c : g.checkpoints) {
      if (!finite({c.x, c.y}) || (c.has_heading && !std::isfinite(c.heading)))
        return finish(INVALID_GOAL, "checkpoint coordinates must be finite", false);
      queue_.push_back(driver::Checkpoint{c.x, c.y, static_cast<bool>(c.has_heading), c.heading});
    }
    path_tolerance_ = g.tolerance > 0 ? g.tolerance : default_position_tolerance_;
    path_max_speed_ = g.max_speed;
    checkpoints_passed_ = 0;
    passed_in_path_ = 0;
    max_cross_track_ = 0.0;
    pending_edits_.clear();
    setTimeout(g.timeout);  // refresh() builds the curve from the pose it has (resume())
  }

  // ---------------------------------------------------------------- control
  void send(const Twist2D& cmd) {
    geometry_msgs::Twist t;
    t.linear.x = cmd.v;
    t.angular.z = cmd.w;
    cmd_pub_.publish(t);
  }

  // Zero at once, no ramp: cancel, new goal, abort, deactivation.
  void stopNow() {
    limiter_.reset();
    send(Twist2D());
  }

  void drive(const Twist2D& desired, double dt) {
    if (!active()) return stopNow();
    send(limiter_.apply(desired, dt));
  }

  std::string avoidanceNow() const {
    if (stopped_now_) return "stopped";
    if (!waypoints_.empty() || detour_active_) return "detour";
    return "none";
  }

  std::string avoidanceSummary() const { return avoidance_used_.empty() ? "none" : avoidance_used_; }

  void noteAvoidance(const std::string& what) {
    if (avoidance_used_.find(what) != std::string::npos) return;
    avoidance_used_ = avoidance_used_.empty() ? what : avoidance_used_ + "+" + what;
  }

  // Returns true when the robot must stand still for an obstacle this period. `route` starts at the robot.
  // On a detour, `insert` receives the waypoints.
  bool avoid(const Pose2D& robot, const std::vector<Point2D>& route, const Point2D& final_target,
             std::vector<Point2D>* insert) {
    stopped_now_ = false;
    if (avoidance_.config().mode == AvoidanceConfig::Mode::OFF) return false;
    const auto obs = obstacles(robot);
    const auto hit = avoidance_.check(route, obs);
    if (!hit.blocked) {
      blocked_since_ = ros::Time();
      return false;
    }
    const bool goal_taken = std::hypot(hit.obstacle.x - final_target.x, hit.obstacle.y - final_target.y) < avoidance_.config().clearance();
    if (avoidance_.config().mode == AvoidanceConfig::Mode::DETOUR && !goal_taken && detours_ < static_cast<uint32_t>(avoidance_.config().max_detours) &&
        avoidance_.detour(hit, obs, insert)) {
      ++detours_;
      noteAvoidance("detour");
      ROS_INFO("driver: opponent at (%.2f, %.2f) on the route, detour via (%.2f, %.2f) (%.2f, %.2f)", hit.obstacle.x,
               hit.obstacle.y, (*insert)[0].x, (*insert)[0].y, (*insert)[1].x, (*insert)[1].y);
      blocked_since_ = ros::Time();
      return false;
    }
    if (blocked_since_.isZero()) {
      blocked_since_ = ros::Time::now();
      ROS_INFO("driver: opponent at (%.2f, %.2f), %.2f m ahead on the route: stopping", hit.obstacle.x, hit.obstacle.y, hit.along);
    }
    stopped_now_ = true;
    noteAvoidance("stopped");
    return true;
  }

  bool blockedTooLong() const {
    return !blocked_since_.isZero() && (ros::Time::now() - blocked_since_).toSec() > avoidance_.config().blocked_timeout;
  }

  void stepGoto(const Pose2D& pose, double dt) {
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
      if (blockedTooLong()) return finish(BLOCKED, "route blocked by an obstacle for longer than avoidance/blocked_timeout", false);
      drive(Twist2D(), dt);  // brake at the deceleration limit: braking_distance allows it
      publishGotoFeedback();
      return;
    }
    // Odometry's twist tells the Autopilot when the wheels have really stopped.
    Twist2D measured;
    const Twist2D* measured_ptr = nullptr;
    if (const auto o = odom_->fresh(max_odom_age_)) {
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
  void startLeg(const Pose2D& pose) {
    detour_active_ = !waypoints_.empty();
    if (waypoints_.empty()) {
      autopilot_.start(goal_, pose);
      return;
    }
    AutopilotGoal leg = goal_;
    leg.target = {waypoints_.front().x, waypoints_.front().y, 0.0};
    leg.position_tolerance = detour_tolerance_;
    leg.final_heading = false;
    leg.allow_reverse = false;
    autopilot_.start(leg, pose);
  }

  void publishGotoFeedback() {
    GotoFeedback f;
    Pose2D pose;
    fusion_.mapPose(&pose);
    f.distance_remaining = std::hypot(goal_.target.x - pose.x, goal_.target.y - pose.y);
    f.progress = waypoints_.empty() && !detour_active_ ? autopilot_.progressPercent() : 0.0;
    f.phase = waiting_.empty() ? Autopilot::phaseName(autopilot_.phase()) : "holding";
    f.avoidance = avoidanceNow();
    f.waiting = waiting_;
    goto_->publishFeedback(f);
  }

  void stepRelative(const Pose2D& pose, double dt) {
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

  void publishRelativeFeedback() {
    if (mode_ == Mode::STRAIGHT) {
      GoStraightFeedback f;
      if (move_started_) {
        f.distance_remaining = straight_.remaining();
        f.progress = straight_.progressPercent();
      }
      f.waiting = waiting_;
      straight_as_->publishFeedback(f);
    } else if (mode_ == Mode::ROTATE) {
      RotateByFeedback f;
      if (move_started_) {
        f.angle_remaining = rotation_.remaining();
        f.progress = rotation_.progressPercent();
      }
      f.waiting = waiting_;
      rotate_as_->publishFeedback(f);
    }
  }

  void rebuildPath(const Pose2D& pose) {
    const HermitePath path(pose, queue_);
    follower_.start(path.sample(path_config_.sample_step), path_tolerance_, path_max_speed_);
    passed_in_path_ = 0;
    nav_msgs::Path msg;
    msg.header.stamp = ros::Time::now();
    msg.header.frame_id = map_frame_;
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
  void popPassed() {
    const int passed = std::min<int>(follower_.segment(), static_cast<int>(queue_.size()));
    if (passed > passed_in_path_) {
      checkpoints_passed_ += passed - passed_in_path_;
      passed_in_path_ = passed;
    }
  }

  void applyEdits(const Pose2D& pose) {
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

  void stepPath(const Pose2D& pose, double dt) {
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
      if (blockedTooLong()) return finish(BLOCKED, "route blocked by an obstacle for longer than avoidance/blocked_timeout", false);
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

  void publishPathFeedback() {
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
    path_as_->publishFeedback(f);
  }

  // End the running goal: stop the wheels and report. `success` only with REACHED.
  void finish(uint8_t code, const std::string& message, bool success) {
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
        end(*goto_, r);
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

  // ---------------------------------------------------------------- state
  AutopilotConfig config_;
  PathFollowerConfig path_config_;
  Autopilot autopilot_;
  StraightMove straight_;
  Rotation rotation_;
  PathFollower follower_;
  Avoidance avoidance_;
  VelocityLimiter limiter_;
  PoseFusion fusion_;

  std::unique_ptr<actionlib::SimpleActionServer<GotoAction>> goto_;
  std::unique_ptr<actionlib::SimpleActionServer<GoStraightAction>> straight_as_;
  std::unique_ptr<actionlib::SimpleActionServer<RotateByAction>> rotate_as_;
  std::unique_ptr<actionlib::SimpleActionServer<FollowPathAction>> path_as_;

  std::shared_ptr<LatestValue<geometry_msgs::PoseWithCovarianceStamped>> pose_;
  std::shared_ptr<LatestValue<LocalizationQuality>> quality_;
  std::shared_ptr<LatestValue<nav_msgs::Odometry>> odom_;
  std::vector<std::shared_ptr<LatestValue<sensor_msgs::Range>>> rangers_;
  std::shared_ptr<LatestValue<geometry_msgs::PointStamped>> opponent_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::map<std::string, Pose2D> mounts_;

  ros::Publisher cmd_pub_, path_pub_;
  ros::Subscriber edit_sub_, diag_sub_;

  Mode mode_ = Mode::NONE;
  ros::Time last_refresh_, last_map_stamp_, timeout_, blocked_since_;
  ros::Time held_since_;        // the running goal holds for a passing fault since then (zero: it drives)
  ros::Time stall_since_;       // commanded to move while odometry reads none since then
  std::string stall_message_;
  std::string waiting_;         // why it holds
  bool move_started_ = false;   // the goal's autopilot / curve / relative move was started from a pose
  GoStraightGoal straight_goal_;
  RotateByGoal rotate_goal_;
  double period_ = 0.02;
  AutopilotGoal goal_;
  std::vector<Point2D> waypoints_;  // detour waypoints before goal_
  bool detour_active_ = false, stopped_now_ = false;
  std::vector<driver::Checkpoint> queue_;   // the follow_path checkpoints of the current curve
  std::deque<PathEdit> pending_edits_;
  int passed_in_path_ = 0;
  uint32_t checkpoints_passed_ = 0;
  double path_tolerance_ = 0.01, path_max_speed_ = 0.0, max_cross_track_ = 0.0;
  uint32_t detours_ = 0;
  std::string avoidance_used_;

  double default_position_tolerance_ = 0.01, default_angle_tolerance_ = 0.035, default_straight_tolerance_ = 0.005;
  bool predict_pose_ = true;
  double max_hold_ = 5.0, stall_timeout_ = 1.0;
  double max_pose_age_ = 0.5, max_odom_age_ = 0.2, min_probability_ = 0.5, detour_tolerance_ = 0.05, obstacle_max_age_ = 0.3;
  std::string motor_status_, base_frame_, map_frame_;
  bool motor_fault_ = false;
  std::string motor_fault_message_;
  unsigned long goals_ = 0, aborted_ = 0, holds_ = 0, stalls_ = 0, edits_dropped_ = 0, tf_errors_ = 0, border_echoes_ = 0;
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(Driver, Driver,
                  "Driver: goto (Autopilot), go_straight, rotate_by and follow_path (Hermite) actions with avoidance, on /hal/drive/cmd_vel.")
