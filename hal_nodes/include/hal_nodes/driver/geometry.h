// Plane geometry shared by the driver's controllers: a pose on the table, a velocity command
// of a differential-drive base, angle wrapping. REP-103: metres, radians, counter-clockwise.
#pragma once

#include <robot_core/geometry.h>

#include <cmath>

namespace hal_nodes {
namespace driver {

struct Point2D {
  double x = 0.0;
  double y = 0.0;
};

using robot_core::Pose2D;

// What a differential-drive base can be told: forward speed and turn rate (geometry_msgs/Twist
// linear.x and angular.z). Wheel speeds are v -/+ w * track / 2.
struct Twist2D {
  double v = 0.0;  // [m/s]
  double w = 0.0;  // [rad/s]
};

// Angles wrap into (-pi, pi] with robot_core's wrapAngle, as in every layer.
using robot_core::wrapAngle;

inline double distance(double ax, double ay, double bx, double by) { return std::hypot(bx - ax, by - ay); }

// Sign with sign(0) = 0.
inline double sign(double x) { return (x > 0.0) - (x < 0.0); }

}  // namespace driver
}  // namespace hal_nodes
