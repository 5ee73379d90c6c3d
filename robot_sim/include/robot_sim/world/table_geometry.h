// The table as obstacles: robot_core's table geometry (borders, and circles for the opponent and
// the game elements) gives the rangers their echoes; the clearance below keeps the opponent on it.
#pragma once

#include <robot_core/table_geometry.h>

#include <algorithm>

namespace robot_sim {

using robot_core::Circle;
using robot_core::TableGeometry;

// Free distance between a circle of radius r at (x, y) and the borders (negative: overlap).
inline double borderClearance(const TableGeometry& table, double x, double y, double r) {
  return std::min({x, table.length() - x, y, table.width() - y}) - r;
}

}  // namespace robot_sim
