// The playing table as the sensors see it: the inside of the rectangle [0, length] x [0, width]
// (x along the length, REP-103 map frame), fixed blocks on it (axis-aligned rectangles) and, per
// query, round things that move (the opponent, game elements). One answer to "how far is the
// first echo in this cone?" for the driver's avoidance, the localization's ranger check, the
// simulator's rangers and (through the Python twin, robot_core.table_geometry) the brain.
#pragma once

#include <vector>

namespace robot_core {

struct Rect {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;  // x0 < x1, y0 < y1 [m]
};

struct Circle {
  double x = 0.0, y = 0.0, r = 0.0;  // centre and radius [m]
};

class TableGeometry {
 public:
  // Throws std::invalid_argument for a table without area or a block with x0 >= x1 or y0 >= y1.
  TableGeometry(double length, double width, std::vector<Rect> blocks = {});

  double length() const { return length_; }
  double width() const { return width_; }
  const std::vector<Rect>& blocks() const { return blocks_; }

  // Whether (x, y) is strictly inside the table and outside every block: a sensor there sees.
  bool open(double x, double y) const;

  // Distance from (x, y) along `angle` to the first border, block or circle [m]. 0 when (x, y)
  // is not open or is inside a circle: a sensor pressed against something reads it at 0.
  // Always finite (the borders close the table); the caller applies its sensor's max range.
  double rayRange(double x, double y, double angle, const std::vector<Circle>& circles = {}) const;

  // Distance from (x, y) to the nearest border, block or circle point inside the cone of full
  // width `beam_width` around `angle`: the first echo of a sonar (its whole cone, not its centre
  // line). beam_width 0 is rayRange. Exact, no ray fan: on a straight edge the nearest point of
  // the cone is the foot of the perpendicular, a corner or where a cone edge ray crosses it; on
  // a circle it is towards the centre, or on a cone edge ray.
  double coneRange(double x, double y, double angle, double beam_width,
                   const std::vector<Circle>& circles = {}) const;

  // Distance from (x, y) to the nearest border or block edge [m]; 0 when (x, y) is not open.
  double distanceToEdge(double x, double y) const;

 private:
  double length_, width_;
  std::vector<Rect> blocks_;
};

}  // namespace robot_core
