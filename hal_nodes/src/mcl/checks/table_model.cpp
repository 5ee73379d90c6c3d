#include "hal_nodes/mcl/checks/table_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hal_nodes::mcl {

TableModel::TableModel(double length, double width, double margin, std::vector<Rect> obstacles)
    : CheckingInput("table", 1.0),
      geometry_(length, width, std::move(obstacles)),
      margin_(margin) {
  if (!(margin >= 0.0) || 2.0 * margin >= std::min(length, width))
    throw std::invalid_argument("table: margin must be >= 0 and leave free space");
  for (const auto& r : geometry_.blocks()) inflated_.push_back({r.x0 - margin_, r.y0 - margin_, r.x1 + margin_, r.y1 + margin_});
}

bool TableModel::isFree(double x, double y) const {
  if (x < margin_ || x > length() - margin_ || y < margin_ || y > width() - margin_) return false;
  for (const auto& r : inflated_)
    if (x > r.x0 && x < r.x1 && y > r.y0 && y < r.y1) return false;
  return true;
}

void TableModel::project(double& x, double& y) const {
  if (!std::isfinite(x) || !std::isfinite(y)) {
    x = 0.5 * length();
    y = 0.5 * width();
  }
  x = std::clamp(x, margin_, length() - margin_);
  y = std::clamp(y, margin_, width() - margin_);
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
      x = std::clamp(x, margin_, length() - margin_);
      y = std::clamp(y, margin_, width() - margin_);
      moved = true;
    }
    if (!moved) break;
  }
}

Pose2D TableModel::sampleFree(Rng& rng) const {
  for (int tries = 0; tries < 1000; ++tries) {
    const double x = rng.uniform(margin_, length() - margin_), y = rng.uniform(margin_, width() - margin_);
    if (isFree(x, y)) return {x, y, rng.uniform(-M_PI, M_PI)};
  }
  return {0.5 * length(), 0.5 * width(), rng.uniform(-M_PI, M_PI)};
}

void TableModel::check(ParticleSet& set, const StepContext&) {
  const std::size_t n = set.size();
  const double* px = set.x.data();
  const double* py = set.y.data();
  double* w = set.w.data();
  const double lo_x = margin_, hi_x = length() - margin_, lo_y = margin_, hi_y = width() - margin_;
  if (inflated_.empty()) {
    for (std::size_t i = 0; i < n; ++i)
      if (px[i] < lo_x || px[i] > hi_x || py[i] < lo_y || py[i] > hi_y) w[i] = 0.0;
  } else {
    for (std::size_t i = 0; i < n; ++i)
      if (!isFree(px[i], py[i])) w[i] = 0.0;
  }
}

}  // namespace hal_nodes::mcl
