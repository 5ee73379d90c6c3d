#include "hal_nodes/driver/hermite_path.h"

#include <algorithm>
#include <cmath>

namespace hal_nodes {
namespace driver {

namespace {
Point2D unit(double dx, double dy) {
  const double n = std::hypot(dx, dy);
  return n > 1e-12 ? Point2D{dx / n, dy / n} : Point2D{0.0, 0.0};
}
double chord(const Point2D& a, const Point2D& b) { return std::hypot(b.x - a.x, b.y - a.y); }
}  // namespace

HermitePath::HermitePath(const Pose2D& start, const std::vector<Checkpoint>& checkpoints) {
  points_.push_back({start.x, start.y});
  for (const auto& c : checkpoints) points_.push_back({c.x, c.y});
  const int n = static_cast<int>(points_.size());
  tangents_.assign(n, Point2D{});
  for (int i = 0; i < n; ++i) {
    const double in = i > 0 ? chord(points_[i - 1], points_[i]) : -1.0;
    const double out = i + 1 < n ? chord(points_[i], points_[i + 1]) : -1.0;
    const double length = in < 0.0 ? out : out < 0.0 ? in : std::min(in, out);
    Point2D dir;
    if (i == 0) {
      dir = {std::cos(start.theta), std::sin(start.theta)};
      // Facing away from the first checkpoint, the robot's heading would loop the curve forwards
      // first (into the corner or the container behind it): start along the chord instead; the
      // follower turns in place onto it.
      if (n > 1) {
        const Point2D to_next = unit(points_[1].x - points_[0].x, points_[1].y - points_[0].y);
        if (dir.x * to_next.x + dir.y * to_next.y < 0.0) dir = to_next;
      }
    } else if (checkpoints[i - 1].has_heading) {
      dir = {std::cos(checkpoints[i - 1].heading), std::sin(checkpoints[i - 1].heading)};
    } else if (i + 1 < n) {
      dir = unit(points_[i + 1].x - points_[i].x, points_[i + 1].y - points_[i].y);
    } else {
      dir = unit(points_[i].x - points_[i - 1].x, points_[i].y - points_[i - 1].y);
    }
    tangents_[i] = {dir.x * std::max(length, 0.0), dir.y * std::max(length, 0.0)};
  }
}

Point2D HermitePath::position(int i, double u) const {
  const double u2 = u * u, u3 = u2 * u;
  const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
  const Point2D &p0 = points_[i], &p1 = points_[i + 1], &m0 = tangents_[i], &m1 = tangents_[i + 1];
  return {h00 * p0.x + h10 * m0.x + h01 * p1.x + h11 * m1.x, h00 * p0.y + h10 * m0.y + h01 * p1.y + h11 * m1.y};
}

Point2D HermitePath::derivative(int i, double u) const {
  const double u2 = u * u;
  const double d00 = 6 * u2 - 6 * u, d10 = 3 * u2 - 4 * u + 1, d01 = -6 * u2 + 6 * u, d11 = 3 * u2 - 2 * u;
  const Point2D &p0 = points_[i], &p1 = points_[i + 1], &m0 = tangents_[i], &m1 = tangents_[i + 1];
  return {d00 * p0.x + d10 * m0.x + d01 * p1.x + d11 * m1.x, d00 * p0.y + d10 * m0.y + d01 * p1.y + d11 * m1.y};
}

Point2D HermitePath::secondDerivative(int i, double u) const {
  const double d00 = 12 * u - 6, d10 = 6 * u - 4, d01 = -12 * u + 6, d11 = 6 * u - 2;
  const Point2D &p0 = points_[i], &p1 = points_[i + 1], &m0 = tangents_[i], &m1 = tangents_[i + 1];
  return {d00 * p0.x + d10 * m0.x + d01 * p1.x + d11 * m1.x, d00 * p0.y + d10 * m0.y + d01 * p1.y + d11 * m1.y};
}

std::vector<PathSample> HermitePath::sample(double step) const {
  std::vector<PathSample> out;
  if (empty()) return out;
  step = std::max(step, 1e-4);
  double s = 0.0;
  for (int i = 0; i < segments(); ++i) {
    const int k = std::max(8, static_cast<int>(std::ceil(chord(points_[i], points_[i + 1]) / step)));
    for (int j = (i == 0 ? 0 : 1); j <= k; ++j) {
      const double u = static_cast<double>(j) / k;
      const Point2D p = position(i, u), d = derivative(i, u);
      if (!out.empty()) s += std::hypot(p.x - out.back().x, p.y - out.back().y);
      PathSample ps;
      ps.x = p.x;
      ps.y = p.y;
      ps.heading = std::hypot(d.x, d.y) > 1e-12 ? std::atan2(d.y, d.x) : (out.empty() ? 0.0 : out.back().heading);
      ps.s = s;
      const Point2D dd = secondDerivative(i, u);
      const double n = std::hypot(d.x, d.y);
      ps.curvature = n > 1e-9 ? (d.x * dd.y - d.y * dd.x) / (n * n * n) : 0.0;
      ps.segment = i;
      out.push_back(ps);
    }
  }
  return out;
}

}  // namespace driver
}  // namespace hal_nodes
