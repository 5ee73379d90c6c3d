#include "hal_nodes/mcl/checks/table_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hal_nodes::mcl {

TableModel::TableModel(double length, double width, double margin, std::vector<Rect> obstacles)
    : CheckingInput("table", 1.0), length_(length), width_(width), margin_(margin), obstacles_(std::move(obstacles)) {
  if (!(length > 0.0) || !(width > 0.0)) throw std::invalid_argument("table: length and width must be > 0");
  if (!(margin >= 0.0) || 2.0 * margin >= std::min(length, width))
    throw std::invalid_argument("table: margin must be >= 0 and leave free space");
  for (const auto& r : obstacles_) {
    if (!(r.x1 > r.x0 && r.y1 > r.y0)) throw std::invalid_argument("table: obstacle rectangles need x0 < x1, y0 < y1");
    inflated_.push_back({r.x0 - margin_, r.y0 - margin_, r.x1 + margin_, r.y1 + margin_});
  }
}

bool TableModel::isFree(double x, double y) const {
  if (x < margin_ || x > length_ - margin_ || y < margin_ || y > width_ - margin_) return false;
  for (const auto& r : inflated_)
    if (x > r.x0 && x < r.x1 && y > r.y0 && y < r.y1) return false;
  return true;
}

void TableModel::project(double& x, double& y) const {
  if (!std::isfinite(x) || !std::isfinite(y)) {
    x = 0.5 * length_;
    y = 0.5 * width_;
  }
  x = std::clamp(x, margin_, length_ - margin_);
  y = std::clamp(y, margin_, width_ - margin_);
  // Out of an obstacle through its nearest side (repeat: pushed into a neighbour).
  for (int pass = 0; pass < 4; ++pass) {
    bool moved = false;
    for (const auto& r : inflated_) {
      if (!(x > r.x0 && x < r.x1 && y > r.y0 && y < r.y1)) continue;
      const double d[4] = {x - r.x0, r.x1 - x, y - r.y0, r.y1 - y};
      const int k = static_cast<int>(std::min_element(d, d + 4) - d);
      if (k == 0) x = r.x0;
      if (k == 1) x = r.x1;
      if (k == 2) y = r.y0;
      if (k == 3) y = r.y1;
      x = std::clamp(x, margin_, length_ - margin_);
      y = std::clamp(y, margin_, width_ - margin_);
      moved = true;
    }
    if (!moved) break;
  }
}

Pose2 TableModel::sampleFree(Rng& rng) const {
  for (int tries = 0; tries < 1000; ++tries) {
    const double x = rng.uniform(margin_, length_ - margin_), y = rng.uniform(margin_, width_ - margin_);
    if (isFree(x, y)) return {x, y, rng.uniform(-M_PI, M_PI)};
  }
  return {0.5 * length_, 0.5 * width_, rng.uniform(-M_PI, M_PI)};
}

namespace {
// Slab test: entry distance of the ray into rectangle r (inf if missed); ray starts outside r.
double rayRect(double x, double y, double c, double s, const Rect& r) {
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  const double o[2] = {x, y}, d[2] = {c, s}, lo[2] = {r.x0, r.y0}, hi[2] = {r.x1, r.y1};
  for (int k = 0; k < 2; ++k) {
    if (std::fabs(d[k]) < 1e-12) {
      if (o[k] < lo[k] || o[k] > hi[k]) return std::numeric_limits<double>::infinity();
    } else {
      double a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
    }
  }
  return t0 <= t1 ? t0 : std::numeric_limits<double>::infinity();
}
}  // namespace

double TableModel::rayCast(double x, double y, double angle, double max_range) const {
  if (x <= 0.0 || x >= length_ || y <= 0.0 || y >= width_) return 0.0;
  for (const auto& r : obstacles_)
    if (x > r.x0 && x < r.x1 && y > r.y0 && y < r.y1) return 0.0;
  const double c = std::cos(angle), s = std::sin(angle);
  // Exit through the table borders.
  double t = std::numeric_limits<double>::infinity();
  if (c > 1e-12) t = std::min(t, (length_ - x) / c);
  if (c < -1e-12) t = std::min(t, -x / c);
  if (s > 1e-12) t = std::min(t, (width_ - y) / s);
  if (s < -1e-12) t = std::min(t, -y / s);
  for (const auto& r : obstacles_) t = std::min(t, rayRect(x, y, c, s, r));
  return std::min(t, max_range);
}

double TableModel::coneRange(double x, double y, double angle, double beam_width, double max_range) const {
  const double half = 0.5 * beam_width;
  if (!(half > 1e-9)) return rayCast(x, y, angle, max_range);
  // The cone's edge rays (0 when (x, y) is off the table or inside an obstacle, at any angle).
  double best = rayCast(x, y, angle - half, max_range);
  if (best <= 0.0) return best;
  best = std::min(best, rayCast(x, y, angle + half, max_range));
  // A point is in the cone when its angle to the axis is at most half: cos >= cos(half), a dot
  // product, no trigonometry per point (this runs for every particle of every ranger reading).
  const double ux = std::cos(angle), uy = std::sin(angle), cos_half = std::cos(half);
  auto consider = [&](double px, double py) {
    const double dx = px - x, dy = py - y, d2 = dx * dx + dy * dy;
    if (d2 >= best * best) return;
    const double d = std::sqrt(d2);
    if (dx * ux + dy * uy >= d * cos_half) best = d;
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
  for (const auto& r : obstacles_) rect(r.x0, r.y0, r.x1, r.y1);
  return best;
}

double TableModel::distanceToEdge(double x, double y) const {
  if (x <= 0.0 || x >= length_ || y <= 0.0 || y >= width_) return 0.0;
  double d = std::min(std::min(x, length_ - x), std::min(y, width_ - y));
  for (const auto& r : obstacles_) {
    const double dx = std::max({r.x0 - x, 0.0, x - r.x1}), dy = std::max({r.y0 - y, 0.0, y - r.y1});
    d = std::min(d, std::hypot(dx, dy));
  }
  return d;
}

void TableModel::check(ParticleSet& set, const StepContext&) {
  const std::size_t n = set.size();
  const double* px = set.x.data();
  const double* py = set.y.data();
  double* w = set.w.data();
  const double lo_x = margin_, hi_x = length_ - margin_, lo_y = margin_, hi_y = width_ - margin_;
  if (inflated_.empty()) {
    for (std::size_t i = 0; i < n; ++i)
      if (px[i] < lo_x || px[i] > hi_x || py[i] < lo_y || py[i] > hi_y) w[i] = 0.0;
  } else {
    for (std::size_t i = 0; i < n; ++i)
      if (!isFree(px[i], py[i])) w[i] = 0.0;
  }
}

}  // namespace hal_nodes::mcl
