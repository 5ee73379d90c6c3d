// The HCL process: a nodelet manager loading every board configured under its private
// namespace (see component_host.h). `nodelet load` into it works too.
#include <ros/ros.h>

#include <robot_core/component_host.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "hcl");
  ros::NodeHandle pnh("~");
  robot_core::ComponentHost host("hcl_drivers", "board");
  if (!host.loadFromParameters(pnh)) return 1;
  ros::spin();
  return 0;
}
