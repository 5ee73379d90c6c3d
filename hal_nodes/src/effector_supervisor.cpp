#include "hal_nodes/effector_supervisor.h"

#include <std_msgs/Bool.h>

namespace hal_nodes {

EffectorSupervisor::EffectorSupervisor(ros::NodeHandle nh) {
  state_pub_ = nh.advertise<std_msgs::Bool>("/effectors/deactivated", 1, true);
  std_msgs::Bool initial;
  initial.data = false;
  state_pub_.publish(initial);
  deactivate_srv_ = nh.advertiseService<std_srvs::Trigger::Request, std_srvs::Trigger::Response>(
      "/effectors/deactivate", [this](std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) { return set(true, res); });
  activate_srv_ = nh.advertiseService<std_srvs::Trigger::Request, std_srvs::Trigger::Response>(
      "/effectors/activate", [this](std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) { return set(false, res); });
}

bool EffectorSupervisor::set(bool deactivated, std_srvs::Trigger::Response& res) {
  std_msgs::Bool msg;
  msg.data = deactivated;
  state_pub_.publish(msg);
  res.success = true;
  res.message = deactivated ? "every effector deactivated" : "effectors active again";
  ROS_WARN("%s", res.message.c_str());
  return true;
}

}  // namespace hal_nodes
