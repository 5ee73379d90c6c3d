// Planar geometry every layer shares (REP-103: x forward, y left, angles counter-clockwise, rad).
// ROS-free, header-only: the device models, the filter's inner loops and the simulator use it.
#pragma once

#include <cmath>

namespace robot_core {

// An angle wrapped into (-pi, pi]. Cheap for an angle already in range, the common case.
inline double wrapAngle(double a) {
  if (a > -M_PI && a <= M_PI) return a;
  a = std::remainder(a, 2.0 * M_PI);  // exact, in [-pi, pi]
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

// The heading [rad] of a unit quaternion (x, y, z, w): its rotation about z (REP-103 yaw).
inline double yawFromQuaternion(double x, double y, double z, double w) {
  return std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
}

// Yaw of any quaternion type with x, y, z, w members (geometry_msgs::Quaternion, ...).
template <class Q>
double yawOf(const Q& q) {
  return yawFromQuaternion(q.x, q.y, q.z, q.w);
}

}  // namespace robot_core
