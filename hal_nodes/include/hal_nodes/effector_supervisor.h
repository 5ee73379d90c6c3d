// The one switch for every effector: services /effectors/deactivate and /effectors/activate
// (std_srvs/Trigger) publish the latched /effectors/deactivated (std_msgs/Bool) that every
// Effector follows, so an effector started later is frozen too. Hosted by hal_node.
//
// It also holds the last word on the match end. The brain publishes the match's end time at the
// start signal, latched, on /effectors/match_end (std_msgs/Time, ROS time); the supervisor
// deactivates every effector at that time by itself. The brain normally does it first; this
// backstop ends the match on time when the brain is dead or stuck at the end, and a hal_node
// respawned after the end reads the latched time and comes up deactivated.
#pragma once

#include <ros/ros.h>
#include <std_msgs/Time.h>
#include <std_srvs/Trigger.h>

namespace hal_nodes {

class EffectorSupervisor {
 public:
  explicit EffectorSupervisor(ros::NodeHandle nh);

 private:
  bool set(bool deactivated, std_srvs::Trigger::Response& res);
  void onMatchEnd(const std_msgs::Time& msg);
  ros::NodeHandle nh_;
  ros::Publisher state_pub_;
  ros::ServiceServer deactivate_srv_;
  ros::ServiceServer activate_srv_;
  ros::Subscriber match_end_sub_;
  ros::Timer match_end_timer_;
};

}  // namespace hal_nodes
