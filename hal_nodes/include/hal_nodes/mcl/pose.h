// A planar pose in the map frame (REP-103: x forward along the table's length, y left,
// theta counter-clockwise from x) and the angle helpers every MCL piece needs.
#pragma once

#include <robot_core/geometry.h>

#include <cmath>

namespace hal_nodes::mcl {

using robot_core::Pose2D;
using robot_core::wrapAngle;  // (-pi, pi], cheap for the small overshoots the filter produces
using robot_core::compose;    // a pose and an increment in its own frame
using robot_core::between;    // the increment from one pose to another

}  // namespace hal_nodes::mcl
