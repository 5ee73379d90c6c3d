// Planar geometry every layer shares (REP-103: x forward, y left, angles counter-clockwise, rad).
// ROS-free, header-only: the device models, the filter's inner loops and the simulator use it.
#pragma once

#include <cmath>

namespace robot_core {

// A pose in the plane: position [m] and heading [rad] (REP-103 yaw), in whatever frame the
// holder says (map for the filter and the driver, the world for the simulator).
struct Pose2D {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;
};

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

// `a` composed with the increment `d` expressed in a's own frame.
inline Pose2D compose(const Pose2D& a, const Pose2D& d) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  return {a.x + c * d.x - s * d.y, a.y + s * d.x + c * d.y, wrapAngle(a.theta + d.theta)};
}

// The increment d such that compose(a, d) == b.
inline Pose2D between(const Pose2D& a, const Pose2D& b) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  const double dx = b.x - a.x, dy = b.y - a.y;
  return {c * dx + s * dy, -s * dx + c * dy, wrapAngle(b.theta - a.theta)};
}

// The pose p expressed the other way round: compose(p, inverse(p)) is the origin.
inline Pose2D inverse(const Pose2D& p) {
  const double c = std::cos(p.theta), s = std::sin(p.theta);
  return {-c * p.x - s * p.y, s * p.x - c * p.y, wrapAngle(-p.theta)};
}

}  // namespace robot_core
