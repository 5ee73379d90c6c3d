// The one switch for every effector: services /effectors/deactivate and /effectors/activate
// (std_srvs/Trigger) publish the latched /effectors/deactivated (std_msgs/Bool) that every
// Effector follows, so an effector started later is frozen too. Hosted by hal_node.
#pragma once

#include <ros/ros.h>
#include <std_srvs/Trigger.h>

namespace hal_nodes {

class EffectorSupervisor {
 public:
  explicit EffectorSupervisor(ros::NodeHandle nh);

 private:
  bool set(bool deactivated, std_srvs::Trigger::Response& res);
  ros::Publisher state_pub_;
  ros::ServiceServer deactivate_srv_;
  ros::ServiceServer activate_srv_;
};

}  // namespace hal_nodes
