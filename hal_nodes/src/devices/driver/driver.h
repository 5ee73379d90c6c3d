// Driver: moves a differential-drive robot, as four preemptible actions under ~ (/hal/driver):
//   goto         absolute pose in the map: the Autopilot (driver/autopilot.h)
//   go_straight  distance along the heading, from odometry alone (driver/relative_moves.h)
//   rotate_by    relative angle, from odometry alone
//   follow_path  checkpoints joined by cubic Hermite segments (driver/hermite_path.h,
//                driver/path_follower.h); ~path_edit (hal_nodes/PathEdit) changes the
//                checkpoints ahead while it runs; the curve is published on ~path (nav_msgs/Path)
// move_base's interface drives the same goto: the action /move_base (move_base_msgs/MoveBaseAction,
// target_pose in the map frame) and /move_base_simple/goal (rviz's "2D Nav Goal"), as move_base
// does it: the simple goal becomes a goal of the /move_base action (driver_move_base.cpp).
// It commands geometry_msgs/Twist on ~cmd_vel_topic (/hal/drive/cmd_vel) only while a goal
// runs; refresh() at ~rate is the control loop. One goal at a time: a goal on any action
// preempts the running one.
//
// Safety. These end the goal at once, wheels stopped, with a result code saying why: cancel /
// new goal (zero published at once, in the callback), /effectors/deactivate (this is an
// Effector), the goal's own timeout.
// A passing fault holds the goal instead: the wheels stop at once, the feedback's `waiting`
// says why, and the goal resumes from where the robot is when the inputs are sound again; only
// a fault lasting longer than ~max_hold [s] (0: end at once) ends the goal with its
// code. The faults: localization older than ~max_pose_age, below ~min_probability or lost
// (goto, follow_path); odometry older than ~max_odom_age (go_straight, rotate_by); the drive
// effector's /diagnostics status at ERROR (~motor_status, a status-name prefix; "" disables). A
// match is lost by a robot that gives up on a 1 s board outage.
// (~predict_pose: the map pose is carried from the newest /odom's stamp to now by its twist.)
// A stall blocks the goal: the wheels commanded (>= 0.05 m/s or 0.3 rad/s) while odometry
// reads no motion for ~stall_timeout [s] (0 disables), e.g. pushing a border where no
// ranger or bumper sees it. A motor held at stall heats up and the goal makes no progress.
// A blocked goal (a stall, or a route blocked past ~avoidance/blocked_timeout) first tries the
// recoveries of ~recovery/behaviors in order (driver/recovery.h: back off where the rear is free,
// turn the other way round, wait), each shown in the feedback's `recovery` and in a WARN, and
// goes on after each; it ends BLOCKED only when the list is used up.
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
//
// Parameters: read and described in configure() (driver_config.cpp, recovery.cpp; the table:
// hal_nodes/PARAMETERS.md, make docs).
#pragma once

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
#include <geometry_msgs/PoseStamped.h>
#include <move_base_msgs/MoveBaseAction.h>

#include <deque>
#include <map>

#include "hal_nodes/device_nodelet.h"
#include "hal_nodes/driver/autopilot.h"
#include "hal_nodes/driver/avoidance.h"
#include "hal_nodes/driver/driver_config.h"
#include "hal_nodes/driver/hermite_path.h"
#include "hal_nodes/driver/path_follower.h"
#include "hal_nodes/driver/pose_fusion.h"
#include "hal_nodes/driver/recovery.h"
#include "hal_nodes/driver/relative_moves.h"

namespace hal_nodes {
namespace driver_device {

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

inline driver::Pose2D poseOf(const geometry_msgs::Pose& p) { return {p.position.x, p.position.y, yawOf(p.orientation)}; }

inline bool finite(std::initializer_list<double> xs) {
  for (double x : xs)
    if (!std::isfinite(x)) return false;
  return true;
}

}  // namespace driver_device

class Driver : public Effector {
 public:
  enum class Mode { NONE, GOTO, STRAIGHT, ROTATE, PATH };
  Driver() : autopilot_(driver::AutopilotConfig()), straight_(driver::AutopilotConfig()), rotation_(driver::AutopilotConfig()),
             follower_(driver::AutopilotConfig(), driver::PathFollowerConfig()), avoidance_(driver::AvoidanceConfig()),
             recovery_(driver::RecoveryConfig(), driver::AutopilotConfig()), limiter_(driver::MotionLimits()) {}

  // Reads the controllers' and the device's configuration (driver_config.h, recovery.h).
  void configure(const robot_core::Params& params) override;
  // Builds the controllers (with the table's size from /table), subscribes, starts the servers.
  void init(DeviceContext& ctx) override;

  // Localization, odometry, the drive effector's status, path edits, and for avoidance the rangers
  // (placed with tf) and the tracked opponent.
  void subscribeInputs(DeviceContext& ctx);
  void startActionServers(ros::NodeHandle& p);
  void refresh() override;
  void deactivate() override;
  void halt() override;
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override;

 private:
  // ---------------------------------------------------------------- inputs
  void updatePose();

  // The map pose, or false with the result code and reason when localization is not usable.
  bool mapPose(driver::Pose2D* pose, uint8_t* code, std::string* why);

  // The newest /odom is already some tens of ms old when a step runs (more on a loaded machine),
  // and arriving at speed that lag alone makes the robot overshoot the goal. With ~predict_pose,
  // the pose is carried from the odometry stamp to now with the odometry's own twist (bounded by
  // ~max_odom_age via fresh()).
  void predictToNow(const nav_msgs::Odometry& o, driver::Pose2D* pose) const;
  bool odomPose(driver::Pose2D* pose);
  void onDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& msg);
  void onPathEdit(const ros::MessageEvent<PathEdit const>& event);

  // Obstacle points in the map from the rangers (via tf) and the tracked opponent.
  std::vector<driver::Point2D> obstacles(const driver::Pose2D& robot);
  bool rangerMount(const std::string& frame, driver::Pose2D* mount);

  // ---------------------------------------------------------------- goals
  bool preemptRequested() const;
  void acceptNewGoals();

  // A goal taking over: the running one of another action is preempted (same action: actionlib did it).
  void takeOver(Mode next);

  // ---------------------------------------------------------------- passing faults
  // Whether the running goal's inputs allow driving now, with the pose to steer by (map for goto
  // and follow_path, odometry for relative moves); if not, the code and reason.
  bool inputsSound(driver::Pose2D* pose, uint8_t* code, std::string* why);

  // Zero speed while the fault lasts, the feedback saying why; past ~max_hold the goal ends.
  void hold(uint8_t code, const std::string& why, const ros::Time& now);

  // The inputs are sound (again, or for the first time since the goal came): a goto or a path
  // is planned from where the robot is now (it may have been pushed while it held); a relative
  // move keeps its target in the odometry frame and is only started if it was not yet.
  void resume(const driver::Pose2D& pose);

  // Commanded to move, odometry reads no motion, for stall_timeout: stalled.
  bool stalled(const ros::Time& now);

  // ---------------------------------------------------------------- recoveries
  // The goal is blocked: the next recovery that applies starts, or the goal ends BLOCKED.
  void onBlocked(const std::string& why);
  // One period of the running recovery; when it is over the goal goes on from where the robot is.
  void stepRecovery(const ros::Time& now, double dt);
  // [m] free behind the robot: the rear rangers' nearest echo (their range where they see
  // nothing); < 0 when one is missing or stale.
  double rearFree() const;
  // [rad] the turn the goal still has to make when it is turning in place, else 0.
  double turnLeft() const;
  void publishFeedback();

  void setTimeout(double t) { timeout_ = t > 0.0 ? ros::Time::now() + ros::Duration(t) : ros::Time(); }

  bool refuseIfInactive();
  bool refuseUntilLocalized();
  void startGoto(const GotoGoal& g, bool from_move_base = false);
  // move_base's interface (driver_move_base.cpp): its goal becomes a goto of ours.
  void startMoveBaseServer(ros::NodeHandle& nh);
  void startMoveBase(const move_base_msgs::MoveBaseGoal& g);
  void onSimpleGoal(const ros::MessageEvent<geometry_msgs::PoseStamped const>& event);
  void endMoveBase(uint8_t code, const std::string& message, bool success);
  void publishMoveBaseFeedback(const driver::Pose2D& pose);
  void startStraight(const GoStraightGoal& g);
  void startRotate(const RotateByGoal& g);
  void startPath(const FollowPathGoal& g);

  // ---------------------------------------------------------------- control
  void send(const driver::Twist2D& cmd);

  // Zero at once, no ramp: cancel, new goal, abort, deactivation.
  void stopNow();
  void drive(const driver::Twist2D& desired, double dt);
  std::string avoidanceNow() const;
  std::string avoidanceSummary() const { return avoidance_used_.empty() ? "none" : avoidance_used_; }

  void noteAvoidance(const std::string& what);

  // Returns true when the robot must stand still for an obstacle this period. `route` starts at the robot.
  // On a detour, `insert` receives the waypoints.
  bool avoid(const driver::Pose2D& robot, const std::vector<driver::Point2D>& route, const driver::Point2D& final_target,
             std::vector<driver::Point2D>* insert) {
    stopped_now_ = false;
    if (avoidance_.config().mode == driver::AvoidanceConfig::Mode::OFF) return false;
    const auto obs = obstacles(robot);
    const auto hit = avoidance_.check(route, obs);
    if (!hit.blocked) {
      blocked_since_ = ros::Time();
      return false;
    }
    const bool goal_taken = std::hypot(hit.obstacle.x - final_target.x, hit.obstacle.y - final_target.y) < avoidance_.config().clearance();
    if (avoidance_.config().mode == driver::AvoidanceConfig::Mode::DETOUR && !goal_taken && detours_ < static_cast<uint32_t>(avoidance_.config().max_detours) &&
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

  bool blockedTooLong() const;
  void stepGoto(const driver::Pose2D& pose, double dt);

  // Aim the autopilot at the next waypoint (passing through, no stop) or the goal itself.
  void startLeg(const driver::Pose2D& pose);
  void publishGotoFeedback();
  void stepRelative(const driver::Pose2D& pose, double dt);
  void publishRelativeFeedback();
  void rebuildPath(const driver::Pose2D& pose);

  // Drop the checkpoints the follower has passed from the queue.
  void popPassed();
  void applyEdits(const driver::Pose2D& pose);
  void stepPath(const driver::Pose2D& pose, double dt);
  void publishPathFeedback();

  // End the running goal: stop the wheels and report. `success` only with REACHED.
  void finish(uint8_t code, const std::string& message, bool success);

  // ---------------------------------------------------------------- state
  driver::AutopilotConfig config_;
  driver::PathFollowerConfig path_config_;
  driver::AvoidanceConfig avoidance_config_;  // as configured; init() adds the table's size
  std::string avoidance_name_;                // qualified ~avoidance, to name it when the table makes it invalid
  driver::RecoveryConfig recovery_config_;
  driver::Autopilot autopilot_;
  driver::StraightMove straight_;
  driver::Rotation rotation_;
  driver::PathFollower follower_;
  driver::Avoidance avoidance_;
  driver::Recovery recovery_;
  driver::VelocityLimiter limiter_;
  driver::PoseFusion fusion_;

  std::unique_ptr<actionlib::SimpleActionServer<GotoAction>> goto_;
  std::unique_ptr<actionlib::SimpleActionServer<GoStraightAction>> straight_as_;
  std::unique_ptr<actionlib::SimpleActionServer<RotateByAction>> rotate_as_;
  std::unique_ptr<actionlib::SimpleActionServer<FollowPathAction>> path_as_;
  std::unique_ptr<actionlib::SimpleActionServer<move_base_msgs::MoveBaseAction>> move_base_;
  bool goto_from_move_base_ = false;  // the running goto is a /move_base goal
  ros::Publisher move_base_goal_pub_;
  ros::Subscriber simple_goal_sub_;

  std::shared_ptr<LatestValue<geometry_msgs::PoseWithCovarianceStamped>> pose_;
  std::shared_ptr<LatestValue<LocalizationQuality>> quality_;
  bool localized_once_ = false;  // localization sound at a goal's start since the driver started
  std::shared_ptr<LatestValue<nav_msgs::Odometry>> odom_;
  std::vector<std::shared_ptr<LatestValue<sensor_msgs::Range>>> rangers_;
  std::vector<std::shared_ptr<LatestValue<sensor_msgs::Range>>> rear_rangers_;  // recovery/rear_rangers
  std::shared_ptr<LatestValue<geometry_msgs::PointStamped>> opponent_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::map<std::string, driver::Pose2D> mounts_;

  ros::Publisher cmd_pub_, path_pub_;
  ros::Subscriber edit_sub_, diag_sub_;

  Mode mode_ = Mode::NONE;
  ros::Time last_refresh_, last_map_stamp_, timeout_, blocked_since_;
  ros::Time held_since_;        // the running goal holds for a passing fault since then (zero: it drives)
  ros::Time stall_since_;       // commanded to move while odometry reads none since then
  std::string stall_message_;
  std::string waiting_;         // why it holds
  bool move_started_ = false;   // the goal's autopilot / curve / relative move was started from a pose
  bool resume_after_recovery_ = false;  // a recovery ended: the goal goes on from where the robot is
  std::string blocked_why_;     // what blocked the goal that a recovery now tries to free
  GoStraightGoal straight_goal_;
  RotateByGoal rotate_goal_;
  double period_ = 0.02;
  driver::AutopilotGoal goal_;
  std::vector<driver::Point2D> waypoints_;  // detour waypoints before goal_
  bool detour_active_ = false, stopped_now_ = false;
  std::vector<driver::Checkpoint> queue_;   // the follow_path checkpoints of the current curve
  std::deque<PathEdit> pending_edits_;
  int passed_in_path_ = 0;
  uint32_t checkpoints_passed_ = 0;
  double path_tolerance_ = 0.01, path_max_speed_ = 0.0, max_cross_track_ = 0.0;
  uint32_t detours_ = 0;
  std::string avoidance_used_;

  driver::DriverDeviceConfig settings_;
  bool motor_fault_ = false;
  std::string motor_fault_message_;
  unsigned long goals_ = 0, aborted_ = 0, holds_ = 0, stalls_ = 0, edits_dropped_ = 0, tf_errors_ = 0, border_echoes_ = 0,
                recoveries_ = 0;
};

}  // namespace hal_nodes
