// A planar pose in the map frame (REP-103: x forward along the table's length, y left,
// theta counter-clockwise from x) and the angle helpers every MCL piece needs.
#pragma once

#include <robot_core/geometry.h>

#include <cmath>

namespace hal_nodes::mcl {

struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;
};

using robot_core::wrapAngle;  // (-pi, pi], cheap for the small overshoots the filter produces

// `a` composed with the increment `d` expressed in a's own frame.
inline Pose2 compose(const Pose2& a, const Pose2& d) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  return {a.x + c * d.x - s * d.y, a.y + s * d.x + c * d.y, wrapAngle(a.theta + d.theta)};
}

// The increment d such that compose(a, d) == b.
inline Pose2 between(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  const double dx = b.x - a.x, dy = b.y - a.y;
  return {c * dx + s * dy, -s * dx + c * dy, wrapAngle(b.theta - a.theta)};
}

}  // namespace hal_nodes::mcl
