#include "robot_sim/world/table_geometry.h"

#include <algorithm>
#include <cmath>

namespace robot_sim {

double TableGeometry::rayCast(double x, double y, double a, double max_range, const std::vector<Circle>& circles) const {
  const double inf = std::numeric_limits<double>::infinity();
  if (x < 0 || x > length_ || y < 0 || y > width_) return inf;
  const double dx = std::cos(a), dy = std::sin(a);
  double best = inf;
  // Borders: the ray leaves the rectangle through one of them.
  if (dx > 1e-12) best = std::min(best, (length_ - x) / dx);
  if (dx < -1e-12) best = std::min(best, -x / dx);
  if (dy > 1e-12) best = std::min(best, (width_ - y) / dy);
  if (dy < -1e-12) best = std::min(best, -y / dy);
  for (const Circle& c : circles) {
    const double ox = c.x - x, oy = c.y - y;
    const double along = ox * dx + oy * dy;
    const double d2 = ox * ox + oy * oy - along * along;
    const double r2 = c.r * c.r;
    if (d2 > r2) continue;
    const double half = std::sqrt(r2 - d2);
    double t = along - half;
    if (t < 0) t = along + half < 0 ? inf : 0.0;  // inside the circle: touching
    best = std::min(best, t);
  }
  return best <= max_range ? best : inf;
}

double TableGeometry::borderClearance(double x, double y, double r) const {
  return std::min({x, length_ - x, y, width_ - y}) - r;
}

}  // namespace robot_sim
