// The Driver device (driver.h): configuration, the control period and the device lifecycle.
#include "driver.h"

namespace hal_nodes {

using namespace driver;
using namespace driver_device;

void Driver::configure(const robot_core::Params& params) {
  // the readers the bench and tests use too
  config_ = readAutopilotConfig(params, robot());
  avoidance_config_ = readAvoidanceConfig(params, config_, robot());
  avoidance_name_ = params.qualified("avoidance");
  settings_ = readDriverDeviceConfig(params);
  path_config_ = readPathFollowerConfig(params);
  recovery_config_ = readRecoveryConfig(params);
}

void Driver::init(DeviceContext& ctx) {
  period_ = 1.0 / ctx.rate;
  // The table's size is the table's, not the driver's: /table, outside the driver's block.
  AvoidanceConfig av = avoidance_config_;
  const robot_core::Params table = robot_core::Params::of(ros::NodeHandle("/table"));
  table.describe("length", "[m] x extent of the table (map frame)");
  av.table_length = table.optionalDouble("length", av.table_length);
  table.describe("width", "[m] y extent of the table (map frame)");
  av.table_width = table.optionalDouble("width", av.table_width);
  const std::string why = av.invalidReason();
  if (!why.empty()) throw robot_core::ParameterError("parameter " + avoidance_name_ + ": " + why);
  const AutopilotConfig& ap = config_;
  autopilot_ = Autopilot(ap);
  straight_ = StraightMove(ap);
  rotation_ = Rotation(ap);
  follower_ = PathFollower(ap, path_config_);
  avoidance_ = Avoidance(av);
  recovery_ = Recovery(recovery_config_, ap);
  limiter_ = VelocityLimiter(ap.limits);
  subscribeInputs(ctx);
  cmd_pub_ = ctx.nh.advertise<geometry_msgs::Twist>(settings_.cmd_vel_topic, 1);
  path_pub_ = ctx.pnh.advertise<nav_msgs::Path>("path", 1, true);
  startActionServers(ctx.pnh);
  startMoveBaseServer(ctx.nh);
}

// Localization, odometry, the drive effector's status, path edits, and for avoidance the rangers
// (placed with tf) and the tracked opponent: these two wake the control loop, so an obstacle
// stops the robot without waiting for the next control period.
void Driver::subscribeInputs(DeviceContext& ctx) {
  pose_ = addInput<geometry_msgs::PoseWithCovarianceStamped>(ctx.nh, settings_.pose_topic, "pose");
  quality_ = addInput<LocalizationQuality>(ctx.nh, settings_.quality_topic, "quality");
  odom_ = addInput<nav_msgs::Odometry>(ctx.nh, settings_.odom_topic, "odometry");
  edit_sub_ = ctx.pnh.subscribe("path_edit", 20, &Driver::onPathEdit, this);
  if (!settings_.motor_status.empty()) diag_sub_ = ctx.nh.subscribe("/diagnostics", 20, &Driver::onDiagnostics, this);
  for (const auto& n : recovery_.config().rear_rangers)
    rear_rangers_.push_back(addInput<sensor_msgs::Range>(ctx.nh, settings_.ranger_prefix + n, "rear ranger " + n));
  if (avoidance_.config().mode == AvoidanceConfig::Mode::OFF) return;
  for (const auto& n : settings_.rangers)
    rangers_.push_back(addInput<sensor_msgs::Range>(ctx.nh, settings_.ranger_prefix + n, "ranger " + n, Wake::kOnArrival));
  if (!settings_.opponent_topic.empty())
    opponent_ = addInput<geometry_msgs::PointStamped>(ctx.nh, settings_.opponent_topic, "opponent", Wake::kOnArrival);
  if (!rangers_.empty()) {
    tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, ctx.nh);
  }
}

void Driver::startActionServers(ros::NodeHandle& p) {
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

void Driver::refresh() {
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
  if (recovery_.running()) return stepRecovery(now, dt);
  Pose2D pose;  // in map (goto, follow_path) or odom (relative moves): read once per period
  uint8_t code;
  std::string why;
  if (!inputsSound(&pose, &code, &why)) return hold(code, why, now);
  if (!held_since_.isZero() || !move_started_ || resume_after_recovery_) resume(pose);
  if (stalled(now)) return onBlocked(stall_message_);
  switch (mode_) {
    case Mode::GOTO: stepGoto(pose, dt); break;
    case Mode::PATH: stepPath(pose, dt); break;
    case Mode::STRAIGHT:
    case Mode::ROTATE: stepRelative(pose, dt); break;
    case Mode::NONE: break;
  }
}

void Driver::deactivate() {
  if (mode_ != Mode::NONE) finish(DEACTIVATED, "effectors deactivated", false);
  stopNow();
}

void Driver::halt() {
  if (mode_ != Mode::NONE) finish(CANCELED, "driver shutting down", false);
}

void Driver::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
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
  stat.add("recoveries", recoveries_);
  stat.add("recovery", recovery_.running() ? recovery_.describe() : std::string("none"));
  stat.addf("last command", "v %.3f m/s, w %.3f rad/s", limiter_.last().v, limiter_.last().w);
}

}  // namespace hal_nodes


HAL_EXPORT_DEVICE(Driver, Driver,
                  "Driver: goto (Autopilot), go_straight, rotate_by and follow_path (Hermite) actions with avoidance, on /hal/drive/cmd_vel.")
