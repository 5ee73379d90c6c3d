// Hosts firmware emulators that need no simulated world (the skeleton's example board).
// Killing this process is unplugging those boards.
#include <ros/ros.h>

#include "robot_sim/firmware/firmware_host.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "firmware_host");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  robot_sim::FirmwareHost host(nh, pnh);
  if (!host.startFromParameters()) return 1;
  ros::spin();
  host.stopAll();
  return 0;
}
