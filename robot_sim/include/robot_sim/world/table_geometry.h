// The table as obstacles: four borders (the inside of the rectangle [0,L]x[0,W]) and circles
// (the opponent, game elements). Ray casts for the rangers, clearances for collisions.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include "robot_sim/world/config.h"

namespace robot_sim {

struct Circle {
  double x = 0.0, y = 0.0, r = 0.0;
};

class TableGeometry {
 public:
  TableGeometry(double length, double width) : length_(length), width_(width) {}
  double length() const { return length_; }
  double width() const { return width_; }

  // Distance along the ray from (x, y) with heading a to the first border or circle, or +inf
  // when nothing is hit within max_range. A ray starting outside the table sees nothing.
  double rayCast(double x, double y, double a, double max_range, const std::vector<Circle>& circles) const;

  // Free distance between a circle of radius r at (x, y) and the borders (negative: overlap).
  double borderClearance(double x, double y, double r) const;

 private:
  double length_, width_;
};

}  // namespace robot_sim
