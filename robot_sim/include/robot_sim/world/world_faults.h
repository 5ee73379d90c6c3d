// The faults injected into the world itself (the firmware emulators have their own):
//   beacon_silent    target: a beacon id "0".."n-1"; it sends nothing
//   wheel_slip       target: a drive motor; magnitude: extra slip fraction (default 0.6)
//   opponent_blocks  the opponent steps in front of our robot, facing it, and stays until the
//                    fault ends; magnitude: the gap [m] (default 0.1)
#pragma once

#include <string>

#include "robot_sim/world/beacon_model.h"
#include "robot_sim/world/opponent.h"
#include "robot_sim/world/robot_body.h"

namespace robot_sim {

struct WorldFaultTargets {
  BeaconModel& beacons;
  RobotBody& robot;
  Opponent& opponent;
  bool opponent_enabled;
  const TableConfig& table;
};

bool isWorldFault(const std::string& kind);

// Starts (`active`) or ends a world fault; false and `why` for an unknown kind or a bad target.
bool applyWorldFault(const std::string& kind, const std::string& target, bool active, double magnitude,
                     const WorldFaultTargets& world, std::string* why);

}  // namespace robot_sim
