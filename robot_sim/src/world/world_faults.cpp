#include "robot_sim/world/world_faults.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "robot_sim/world/diff_drive.h"

namespace robot_sim {

bool isWorldFault(const std::string& kind) {
  return kind == "beacon_silent" || kind == "wheel_slip" || kind == "opponent_blocks";
}

bool applyWorldFault(const std::string& kind, const std::string& target, bool active, double magnitude,
                     const WorldFaultTargets& world, std::string* why) {
  if (kind == "beacon_silent") {
    char* end = nullptr;
    const long id = std::strtol(target.c_str(), &end, 10);
    const long count = static_cast<long>(world.beacons.count());
    if (target.empty() || *end || id < 0 || id >= count) {
      if (why) *why = "beacon_silent: target must be a beacon id 0.." + std::to_string(count - 1);
      return false;
    }
    world.beacons.setSilent(static_cast<int>(id), active);
    return true;
  }
  if (kind == "wheel_slip") {
    const double slip = active ? (magnitude > 0.0 ? std::min(magnitude, 1.0) : 0.6) : 0.0;
    if (!world.robot.setExtraSlip(target, slip)) {
      if (why) *why = "wheel_slip: target must be a drive motor (the robot's motors with drive: left or right)";
      return false;
    }
    return true;
  }
  if (kind == "opponent_blocks") {
    if (!world.opponent_enabled) {
      if (why) *why = "opponent_blocks: the opponent is disabled (sim/world/opponent/enabled)";
      return false;
    }
    if (active) {
      const Pose2D& us = world.robot.pose();
      const double gap = magnitude > 0.0 ? magnitude : 0.1;
      const double d = world.robot.footprint().reach(0.0) + world.opponent.radius() + gap;
      Pose2D p{us.x + d * std::cos(us.theta), us.y + d * std::sin(us.theta), wrapAngle(us.theta + M_PI)};
      const double r = world.opponent.radius();
      p.x = std::clamp(p.x, r, world.table.length - r);
      p.y = std::clamp(p.y, r, world.table.width - r);
      world.opponent.place(p, true);
    } else {
      world.opponent.place(world.opponent.pose(), false);
    }
    return true;
  }
  if (why) *why = "not a world fault: " + kind;
  return false;
}

}  // namespace robot_sim
