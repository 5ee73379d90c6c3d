#include "robot_sim/world/footprint.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace robot_sim {

namespace {
double cross(const Point2D& o, const Point2D& a, const Point2D& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Proper or touching intersection of segments ab and cd.
bool segmentsIntersect(const Point2D& a, const Point2D& b, const Point2D& c, const Point2D& d) {
  const double d1 = cross(c, d, a), d2 = cross(c, d, b), d3 = cross(a, b, c), d4 = cross(a, b, d);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  auto on = [](const Point2D& p, const Point2D& q, const Point2D& r, double side) {
    return std::abs(side) < 1e-12 && std::min(p.x, q.x) - 1e-12 <= r.x && r.x <= std::max(p.x, q.x) + 1e-12 &&
           std::min(p.y, q.y) - 1e-12 <= r.y && r.y <= std::max(p.y, q.y) + 1e-12;
  };
  return on(c, d, a, d1) || on(c, d, b, d2) || on(a, b, c, d3) || on(a, b, d, d4);
}

Point2D unit(double x, double y) {
  const double n = std::hypot(x, y);
  return n > 1e-12 ? Point2D{x / n, y / n} : Point2D{1.0, 0.0};
}
}  // namespace

Footprint::Footprint(std::vector<Point2D> points) : points_(std::move(points)) {
  const std::size_t n = points_.size();
  if (n < 3) throw ConfigError("footprint: needs at least 3 vertices [x, y] in base_link");
  double area2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Point2D& a = points_[i];
    const Point2D& b = points_[(i + 1) % n];
    if (!std::isfinite(a.x) || !std::isfinite(a.y)) throw ConfigError("footprint: vertices must be finite");
    area2 += a.x * b.y - b.x * a.y;
    bounding_radius_ = std::max(bounding_radius_, std::hypot(a.x, a.y));
  }
  if (std::abs(area2) < 1e-8) throw ConfigError("footprint: the polygon has no area");
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      if (j == i + 1 || (i == 0 && j == n - 1)) continue;  // neighbours share a vertex
      if (segmentsIntersect(points_[i], points_[(i + 1) % n], points_[j], points_[(j + 1) % n]))
        throw ConfigError("footprint: sides " + std::to_string(i) + " and " + std::to_string(j) +
                          " cross (list the vertices in order around the outline)");
    }
  if (!insidePolygon(points_, 0.0, 0.0))
    throw ConfigError("footprint: base_link's origin (0, 0) must be inside the outline");
}

std::vector<Point2D> Footprint::regular(double radius, int n) {
  std::vector<Point2D> out;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    out.push_back({radius * std::cos(a), radius * std::sin(a)});
  }
  return out;
}

Footprint Footprint::circle(double radius) {
  if (!(radius > 0.0) || !std::isfinite(radius)) throw ConfigError("footprint: a circle needs a positive radius");
  Footprint f;
  f.bounding_radius_ = radius;
  return f;
}

Footprint robotFootprint(const RobotConfig& robot) {
  return robot.footprint.empty() ? Footprint::circle(robot.radius) : Footprint(robot.footprint);
}

double Footprint::reach(double angle) const {
  if (isCircle()) return bounding_radius_;
  const double ux = std::cos(angle), uy = std::sin(angle);
  double best = -std::numeric_limits<double>::infinity();
  for (const Point2D& p : points_) best = std::max(best, p.x * ux + p.y * uy);
  return best;
}

std::vector<Point2D> Footprint::placed(const Pose2D& pose, int segments) const {
  const std::vector<Point2D> local = isCircle() ? regular(bounding_radius_, std::max(segments, 3)) : points_;
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  std::vector<Point2D> out;
  out.reserve(local.size());
  for (const Point2D& p : local) out.push_back({pose.x + c * p.x - s * p.y, pose.y + s * p.x + c * p.y});
  return out;
}

Contact Footprint::wallContact(const Pose2D& pose, const Point2D& normal, double offset) const {
  Contact c;
  c.normal = normal;
  if (isCircle()) {
    c.clearance = offset - (pose.x * normal.x + pose.y * normal.y) - bounding_radius_;
    c.point = {pose.x + normal.x * bounding_radius_, pose.y + normal.y * bounding_radius_};
    return c;
  }
  // A flat side against the wall touches along it: the middle of the vertices within 1 mm of the deepest.
  const std::vector<Point2D> poly = placed(pose);
  auto free = [&](const Point2D& p) { return offset - (p.x * normal.x + p.y * normal.y); };
  c.clearance = std::numeric_limits<double>::infinity();
  for (const Point2D& p : poly) c.clearance = std::min(c.clearance, free(p));
  int n = 0;
  for (const Point2D& p : poly)
    if (free(p) <= c.clearance + 1e-3) {
      c.point.x += p.x;
      c.point.y += p.y;
      ++n;
    }
  c.point.x /= n;
  c.point.y /= n;
  return c;
}

std::array<Contact, 4> Footprint::borderContacts(const Pose2D& pose, double length, double width) const {
  return {wallContact(pose, {-1.0, 0.0}, 0.0), wallContact(pose, {1.0, 0.0}, length),
          wallContact(pose, {0.0, -1.0}, 0.0), wallContact(pose, {0.0, 1.0}, width)};
}

Contact Footprint::borderContact(const Pose2D& pose, double length, double width) const {
  const auto all = borderContacts(pose, length, width);
  return *std::min_element(all.begin(), all.end(),
                           [](const Contact& a, const Contact& b) { return a.clearance < b.clearance; });
}

Contact Footprint::circleContact(const Pose2D& pose, const Circle& other) const {
  if (!isCircle()) return robot_sim::circleContact(placed(pose), other);
  Contact c;
  c.normal = unit(other.x - pose.x, other.y - pose.y);
  c.clearance = std::hypot(other.x - pose.x, other.y - pose.y) - bounding_radius_ - other.r;
  c.point = {pose.x + c.normal.x * bounding_radius_, pose.y + c.normal.y * bounding_radius_};
  return c;
}

bool Footprint::pushOut(const Pose2D& pose, Circle& other) const {
  if (!isCircle()) return robot_sim::pushOut(placed(pose), other);
  const Contact c = circleContact(pose, other);
  if (c.clearance >= 0.0) return false;
  other.x = c.point.x + c.normal.x * other.r;
  other.y = c.point.y + c.normal.y * other.r;
  return true;
}

bool insidePolygon(const std::vector<Point2D>& poly, double x, double y) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Point2D& a = poly[i];
    const Point2D& b = poly[j];
    if ((a.y > y) != (b.y > y) && x < (b.x - a.x) * (y - a.y) / (b.y - a.y) + a.x) in = !in;
  }
  return in;
}

Contact circleContact(const std::vector<Point2D>& poly, const Circle& circle) {
  double best = std::numeric_limits<double>::infinity();
  Point2D q;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Point2D& a = poly[i];
    const Point2D& b = poly[(i + 1) % poly.size()];
    const double ex = b.x - a.x, ey = b.y - a.y;
    const double len2 = ex * ex + ey * ey;
    const double t = len2 > 0.0 ? std::clamp(((circle.x - a.x) * ex + (circle.y - a.y) * ey) / len2, 0.0, 1.0) : 0.0;
    const Point2D p{a.x + t * ex, a.y + t * ey};
    const double d = std::hypot(circle.x - p.x, circle.y - p.y);
    if (d < best) {
      best = d;
      q = p;
    }
  }
  Contact c;
  c.point = q;
  const bool inside = insidePolygon(poly, circle.x, circle.y);
  if (best > 1e-9) {
    c.normal = inside ? unit(q.x - circle.x, q.y - circle.y) : unit(circle.x - q.x, circle.y - q.y);
  } else {
    // The centre on the outline: out from the middle of the vertices.
    double mx = 0.0, my = 0.0;
    for (const Point2D& p : poly) mx += p.x, my += p.y;
    c.normal = unit(q.x - mx / poly.size(), q.y - my / poly.size());
  }
  c.clearance = inside ? -best - circle.r : best - circle.r;
  return c;
}

bool pushOut(const std::vector<Point2D>& poly, Circle& circle) {
  const Contact c = circleContact(poly, circle);
  if (c.clearance >= 0.0) return false;
  circle.x = c.point.x + c.normal.x * circle.r;
  circle.y = c.point.y + c.normal.y * circle.r;
  return true;
}

}  // namespace robot_sim
