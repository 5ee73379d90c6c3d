// A rigid outline moving among fixed obstacles (the table's borders, round robots): only the
// part of a motion that goes into an obstacle is cancelled. A robot slides along a wall it meets
// at an angle and turns in place against a round opponent; pushed straight into something, its
// wheels stall.
#pragma once

#include <vector>

#include "robot_sim/world/footprint.h"

namespace robot_sim {

struct Obstacles {
  double table_length = 3.0;      // the borders: the inside of [0, length] x [0, width]
  double table_width = 2.1;
  std::vector<Circle> circles;    // the opponent (and anything round that is not pushed)
};

struct ResolvedMotion {
  Pose2D pose;              // where the outline ends up
  bool left_stalled = false;   // the wheel's share of the motion was mostly cancelled
  bool right_stalled = false;
  bool cancelled = false;   // some of the motion went into an obstacle
};

// Moves `outline` from `now` towards `next` (one integration step). An overlap already there is
// allowed to stay but never to deepen: the outline is pushed back out of each obstacle along the
// contact normal by what the step added. A wheel (at +-wheel_base/2) stalls when less than half of
// the ground travel it asked for happens; when both stall the robot stays where it was, the
// motors stalled. When no push-out frees the outline (wedged between two obstacles), the step's
// translation alone is tried, then its turn alone, then nothing.
ResolvedMotion resolveMotion(const Footprint& outline, const Pose2D& now, const Pose2D& next,
                             const Obstacles& obstacles, double wheel_base);

// The nearest obstacle to the outline at `pose` (clearance, point and normal).
Contact nearestContact(const Footprint& outline, const Pose2D& pose, const Obstacles& obstacles);

}  // namespace robot_sim
