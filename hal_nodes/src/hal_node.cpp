// The HAL process: a nodelet manager loading every device configured under its private
// namespace (robot_core/component_host.h), plus the effector supervisor.
#include <robot_core/component_host.h>
#include <ros/ros.h>

#include "hal_nodes/effector_supervisor.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "hal");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  hal_nodes::EffectorSupervisor supervisor(nh);
  robot_core::ComponentHost host("hal_nodes", "device");
  if (!host.loadFromParameters(pnh)) return 1;
  ros::spin();
  return 0;
}
