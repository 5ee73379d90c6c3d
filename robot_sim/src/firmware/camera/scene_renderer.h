// Renders what a camera sees of the simulated world (a WorldSnapshot): the table, its
// borders, the game elements, the opponent and (for a fixed camera) our robot. Two mounts:
//   top    a fixed camera above the table looking straight down (the whole table in view)
//   front  a pinhole camera on the robot at (x, 0, z) in base_link, pitched down by `pitch`
// Flat colours, no lighting: enough for colour/shape-based vision code to be developed
// without hardware (balls by colour, columns, the opponent as a dark cylinder).
#pragma once

#include <opencv2/core.hpp>

#include <string>

#include "robot_sim/world/world.h"

namespace robot_sim {

struct CameraModel {
  std::string mount = "top";  // "top" | "front"
  int width = 320;
  int height = 240;
  double x = 0.12;            // front: mount in base_link [m]
  double z = 0.30;            // front: height above the floor [m]
  double pitch = 0.35;        // front: downward tilt [rad]
  double hfov = 1.05;         // front: horizontal field of view [rad] (~60 deg)
};

// BGR colour of an element kind ("ball_red", "ball_white", "column_green", ...).
cv::Scalar elementColour(const std::string& kind);
extern const cv::Scalar kTableColour;     // the playing surface
extern const cv::Scalar kOutsideColour;   // floor beyond the table
extern const cv::Scalar kOpponentColour;
extern const cv::Scalar kRobotColour;

cv::Mat renderScene(const WorldSnapshot& world, const CameraModel& camera);

}  // namespace robot_sim
