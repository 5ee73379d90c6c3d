// The Driver device (driver.h): move_base's interface for the tools and code written for it.
// A /move_base goal (move_base_msgs/MoveBaseAction) is a goto to its target_pose with the
// driver's default tolerances; it ends SUCCEEDED at the pose, PREEMPTED on cancel or when any
// newer goal takes over, ABORTED with the goto's reason otherwise (text in the status), as
// move_base's states go. /move_base_simple/goal (geometry_msgs/PoseStamped, rviz's "2D Nav Goal")
// is sent to the action as a new goal, as move_base does, so it preempts like any other.
// Only the map frame is accepted: the driver plans in it and keeps no tf of other frames.
#include <cmath>

#include "driver.h"

#include <robot_core/command_gate.h>

namespace hal_nodes {

using namespace driver;
using namespace driver_device;

void Driver::startMoveBaseServer(ros::NodeHandle& nh) {
  move_base_ = std::make_unique<actionlib::SimpleActionServer<move_base_msgs::MoveBaseAction>>(nh, "/move_base", false);
  auto stop = [this]() { stopNow(); };
  move_base_->registerGoalCallback(stop);
  move_base_->registerPreemptCallback(stop);
  move_base_->start();
  move_base_goal_pub_ = nh.advertise<move_base_msgs::MoveBaseActionGoal>("/move_base/goal", 1);
  simple_goal_sub_ = nh.subscribe("/move_base_simple/goal", 1, &Driver::onSimpleGoal, this);
}

void Driver::onSimpleGoal(const ros::MessageEvent<geometry_msgs::PoseStamped const>& event) {
  if (!robot_core::CommandGate::instance().accept(event.getPublisherName(), "/move_base_simple/goal")) return;
  const geometry_msgs::PoseStamped::ConstPtr& goal = event.getConstMessage();
  move_base_msgs::MoveBaseActionGoal g;
  g.header.stamp = ros::Time::now();  // an empty goal id: actionlib gives it one
  g.goal.target_pose = *goal;
  ROS_INFO("driver: /move_base_simple/goal (%.3f, %.3f) in '%s' -> /move_base", goal->pose.position.x,
           goal->pose.position.y, goal->header.frame_id.c_str());
  move_base_goal_pub_.publish(g);
}

void Driver::startMoveBase(const move_base_msgs::MoveBaseGoal& g) {
  const auto& p = g.target_pose.pose;
  const auto& q = p.orientation;
  std::string frame = g.target_pose.header.frame_id;
  if (!frame.empty() && frame[0] == '/') frame = frame.substr(1);
  const double norm = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  // What move_base refuses too: a quaternion that is not a rotation about z.
  const bool planar = std::isfinite(norm) && std::fabs(norm - 1.0) < 1e-3 && std::fabs(q.x) < 1e-3 && std::fabs(q.y) < 1e-3;
  GotoGoal goto_goal;
  goto_goal.x = p.position.x;
  goto_goal.y = p.position.y;
  goto_goal.angle = planar ? yawOf(q) : 0.0;
  startGoto(goto_goal, true);
  if (mode_ != Mode::GOTO) return;  // refused (effectors inactive, not localized yet): aborted
  if (frame != settings_.map_frame)
    return finish(INVALID_GOAL, "target_pose in frame '" + frame + "': send it in '" + settings_.map_frame + "'", false);
  if (!planar) return finish(INVALID_GOAL, "target_pose orientation is not a unit quaternion about z", false);
}

void Driver::endMoveBase(uint8_t code, const std::string& message, bool success) {
  goto_from_move_base_ = false;
  const move_base_msgs::MoveBaseResult r;
  if (success) move_base_->setSucceeded(r, message);
  else if (!move_base_->isActive()) return;
  else if (code == CANCELED) move_base_->setPreempted(r, message);
  else move_base_->setAborted(r, message);
}

void Driver::publishMoveBaseFeedback(const Pose2D& pose) {
  move_base_msgs::MoveBaseFeedback f;
  f.base_position.header.stamp = ros::Time::now();
  f.base_position.header.frame_id = settings_.map_frame;
  f.base_position.pose.position.x = pose.x;
  f.base_position.pose.position.y = pose.y;
  f.base_position.pose.orientation.z = std::sin(pose.theta / 2.0);
  f.base_position.pose.orientation.w = std::cos(pose.theta / 2.0);
  move_base_->publishFeedback(f);
}

}  // namespace hal_nodes
