#include "robot_core/table_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace robot_core {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// Slab test: entry distance of the ray (x, y) + t (c, s) into rectangle r, inf if it misses.
// The ray starts outside r.
double rayRect(double x, double y, double c, double s, const Rect& r) {
  double t0 = 0.0, t1 = kInf;
  const double o[2] = {x, y}, d[2] = {c, s}, lo[2] = {r.x0, r.y0}, hi[2] = {r.x1, r.y1};
  for (int k = 0; k < 2; ++k) {
    if (std::fabs(d[k]) < 1e-12) {
      if (o[k] < lo[k] || o[k] > hi[k]) return kInf;
    } else {
      double a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
    }
  }
  return t0 <= t1 ? t0 : kInf;
}

// Entry distance of the ray into circle k: 0 when it starts inside, inf when it misses.
double rayCircle(double x, double y, double c, double s, const Circle& k) {
  const double ox = k.x - x, oy = k.y - y;
  const double along = ox * c + oy * s;
  const double d2 = ox * ox + oy * oy - along * along;
  const double r2 = k.r * k.r;
  if (d2 > r2) return kInf;
  const double half_chord = std::sqrt(r2 - d2);
  const double t = along - half_chord;
  if (t >= 0.0) return t;
  return along + half_chord < 0.0 ? kInf : 0.0;  // behind the ray, or around its start
}
}  // namespace

TableGeometry::TableGeometry(double length, double width, std::vector<Rect> blocks)
    : length_(length), width_(width), blocks_(std::move(blocks)) {
  if (!(length > 0.0) || !(width > 0.0)) throw std::invalid_argument("table: length and width must be > 0");
  for (const Rect& r : blocks_)
    if (!(r.x1 > r.x0 && r.y1 > r.y0)) throw std::invalid_argument("table: blocks need x0 < x1 and y0 < y1");
}

bool TableGeometry::open(double x, double y) const {
  if (!(x > 0.0 && x < length_ && y > 0.0 && y < width_)) return false;  // also NaN
  for (const Rect& r : blocks_)
    if (x > r.x0 && x < r.x1 && y > r.y0 && y < r.y1) return false;
  return true;
}

double TableGeometry::rayRange(double x, double y, double angle, const std::vector<Circle>& circles) const {
  if (!open(x, y)) return 0.0;
  const double c = std::cos(angle), s = std::sin(angle);
  // The ray leaves the table through one of its borders.
  double t = kInf;
  if (c > 1e-12) t = std::min(t, (length_ - x) / c);
  if (c < -1e-12) t = std::min(t, -x / c);
  if (s > 1e-12) t = std::min(t, (width_ - y) / s);
  if (s < -1e-12) t = std::min(t, -y / s);
  for (const Rect& r : blocks_) t = std::min(t, rayRect(x, y, c, s, r));
  for (const Circle& k : circles) t = std::min(t, rayCircle(x, y, c, s, k));
  return t;
}

double TableGeometry::coneRange(double x, double y, double angle, double beam_width,
                                const std::vector<Circle>& circles) const {
  const double half = 0.5 * beam_width;
  if (!(half > 1e-9)) return rayRange(x, y, angle, circles);
  // The cone's edge rays (0 when (x, y) is not open or inside a circle, at any angle).
  double best = rayRange(x, y, angle - half, circles);
  if (best <= 0.0) return best;
  best = std::min(best, rayRange(x, y, angle + half, circles));
  // A point is in the cone when its angle to the axis is at most half: cos >= cos(half), a dot
  // product, no trigonometry per point (the filter asks this for every particle and reading).
  const double ux = std::cos(angle), uy = std::sin(angle), cos_half = std::cos(half);
  auto inCone = [&](double dx, double dy, double d) { return dx * ux + dy * uy >= d * cos_half; };
  auto consider = [&](double px, double py) {
    const double dx = px - x, dy = py - y, d2 = dx * dx + dy * dy;
    if (d2 >= best * best) return;
    const double d = std::sqrt(d2);
    if (inCone(dx, dy, d)) best = d;
  };
  // On each edge of an axis-aligned rectangle the nearest point of the cone is the foot of the
  // perpendicular, a corner, or where an edge ray crosses it (already in best).
  auto rect = [&](double x0, double y0, double x1, double y1) {
    const double fx = std::clamp(x, x0, x1), fy = std::clamp(y, y0, y1);
    consider(fx, y0);
    consider(fx, y1);
    consider(x0, fy);
    consider(x1, fy);
    consider(x0, y0);
    consider(x1, y0);
    consider(x0, y1);
    consider(x1, y1);
  };
  rect(0.0, 0.0, length_, width_);
  for (const Rect& r : blocks_) rect(r.x0, r.y0, r.x1, r.y1);
  // A circle's nearest point lies towards its centre; when that direction is outside the cone,
  // the nearest point inside it is on an edge ray (distances along the circle grow away from it).
  for (const Circle& k : circles) {
    const double dx = k.x - x, dy = k.y - y, d = std::hypot(dx, dy);
    if (d - k.r < best && inCone(dx, dy, d)) best = d - k.r;
  }
  return best;
}

double TableGeometry::distanceToEdge(double x, double y) const {
  if (!open(x, y)) return 0.0;
  double d = std::min(std::min(x, length_ - x), std::min(y, width_ - y));
  for (const Rect& r : blocks_) {
    const double dx = std::max({r.x0 - x, 0.0, x - r.x1}), dy = std::max({r.y0 - y, 0.0, y - r.y1});
    d = std::min(d, std::hypot(dx, dy));
  }
  return d;
}

}  // namespace robot_core
