// Starts the emulators configured under a private namespace: every key whose value is a
// dictionary with a `type` is one board (`enabled: false` skips it). Used by the
// firmware_host node (no world) and by the simulator (with the world).
#pragma once

#include <ros/ros.h>

#include <map>
#include <memory>
#include <string>

#include "robot_sim/firmware/firmware.h"

namespace robot_sim {

class FirmwareHost {
 public:
  FirmwareHost(ros::NodeHandle nh, ros::NodeHandle pnh, World* world = nullptr);
  ~FirmwareHost();

  // Starts every configured emulator; on a bad configuration prints one line naming the
  // parameter and allowed values and returns false.
  bool startFromParameters();
  // The emulator of board `name`, or null.
  Firmware* find(const std::string& name) const;
  const std::map<std::string, std::unique_ptr<Firmware>>& all() const { return firmware_; }
  void stopAll();

 private:
  ros::NodeHandle nh_;
  ros::NodeHandle pnh_;
  World* world_;
  std::map<std::string, std::unique_ptr<Firmware>> firmware_;
};

}  // namespace robot_sim
