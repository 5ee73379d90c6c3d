#include "hal_nodes/driver/avoidance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <robot_core/table_geometry.h>

namespace hal_nodes {
namespace driver {

std::string AvoidanceConfig::invalidReason() const {
  if (!(robot_radius > 0.0)) return "robot_radius must be > 0";
  if (!(opponent_radius >= 0.0)) return "opponent_radius must be >= 0";
  if (!(margin >= 0.0)) return "margin must be >= 0";
  if (!(braking_distance > 0.0)) return "braking_distance must be > 0";
  if (!(detection_distance >= braking_distance + clearance()))
    return "detection_distance must be >= braking_distance + robot_radius + opponent_radius + margin";
  if (!(border_margin >= 0.0)) return "border_margin must be >= 0";
  if (!(border_echo_tolerance >= 0.0)) return "border_echo_tolerance must be >= 0";
  if (!(table_length > 0.0 && table_width > 0.0)) return "table size must be > 0";
  if (!(blocked_timeout > 0.0)) return "blocked_timeout must be > 0";
  if (max_detours < 0) return "max_detours must be >= 0";
  return "";
}

bool AvoidanceConfig::parseMode(const std::string& s, Mode* mode) {
  if (s == "off") *mode = Mode::OFF;
  else if (s == "stop") *mode = Mode::STOP;
  else if (s == "detour") *mode = Mode::DETOUR;
  else return false;
  return true;
}

bool Avoidance::plausibleObstacle(const Point2D& p) const {
  const double b = config_.border_margin;
  return std::isfinite(p.x) && std::isfinite(p.y) && p.x > b && p.y > b && p.x < config_.table_length - b &&
         p.y < config_.table_width - b;
}

double Avoidance::borderRange(const Pose2D& sensor, double field_of_view) const {
  if (!(config_.table_length > 0.0 && config_.table_width > 0.0)) return 0.0;  // an invalid config sees only border
  const robot_core::TableGeometry table(config_.table_length, config_.table_width);
  return table.coneRange(sensor.x, sensor.y, sensor.theta, std::max(0.0, field_of_view));
}

bool Avoidance::borderExplains(const Pose2D& sensor, double field_of_view, double range) const {
  return range >= borderRange(sensor, field_of_view) - config_.border_echo_tolerance;
}

bool Avoidance::fits(const Point2D& p) const {
  const double r = config_.robot_radius + config_.margin;
  return p.x > r && p.y > r && p.x < config_.table_length - r && p.y < config_.table_width - r;
}

Avoidance::Hit Avoidance::check(const std::vector<Point2D>& route, const std::vector<Point2D>& obstacles) const {
  Hit best;
  if (route.size() < 2 || obstacles.empty()) return best;
  const double clearance = config_.clearance();
  double s0 = 0.0;
  for (std::size_t i = 0; i + 1 < route.size() && s0 < config_.detection_distance; ++i) {
    const Point2D &a = route[i], &b = route[i + 1];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    if (len < 1e-9) continue;
    const Point2D u{(b.x - a.x) / len, (b.y - a.y) / len};
    const double usable = std::min(len, config_.detection_distance - s0);
    for (const auto& o : obstacles) {
      // Where on this segment our footprint first comes within `clearance` of the point.
      const double tp = (o.x - a.x) * u.x + (o.y - a.y) * u.y;
      const double h = std::fabs(-(o.x - a.x) * u.y + (o.y - a.y) * u.x);
      if (h >= clearance) continue;
      if (i == 0 && tp <= 0.0) continue;  // beside or behind the robot: not in the way of where it goes
      if (i == 0 && std::hypot(o.x - a.x, o.y - a.y) < clearance) {
        // Already this near (an echo beside us after a stop): the echo is the opponent's near
        // side, its centre an opponent radius further along the ray. Blocked only if the route
        // passes that centre closer than the clearance; else every route with a forward part
        // would be blocked and the robot could never leave.
        const double d0 = std::hypot(o.x - a.x, o.y - a.y);
        const Point2D c{o.x + config_.opponent_radius * (o.x - a.x) / std::max(d0, 1e-9),
                        o.y + config_.opponent_radius * (o.y - a.y) / std::max(d0, 1e-9)};
        const double tc = (c.x - a.x) * u.x + (c.y - a.y) * u.y;
        const double hc = std::fabs(-(c.x - a.x) * u.y + (c.y - a.y) * u.x);
        if (tc <= 0.0 || hc >= clearance) continue;
      }
      const double half = std::sqrt(clearance * clearance - h * h);
      if (tp + half < 0.0 || tp - half > usable) continue;
      const double along = s0 + std::max(0.0, tp - half);
      if (!best.blocked || along < best.along) {
        best.blocked = true;
        best.along = along;
        best.obstacle = o;
        best.direction = u;
      }
    }
    s0 += len;
  }
  return best;
}

bool Avoidance::detour(const Hit& hit, const std::vector<Point2D>& obstacles, std::vector<Point2D>* waypoints) const {
  if (!hit.blocked) return false;
  const Point2D u = hit.direction, n{-u.y, u.x};
  const double side = config_.clearance() + config_.margin;  // lateral offset of the detour
  const double ahead = config_.clearance();                  // before / after the obstacle
  const Point2D& o = hit.obstacle;
  // Prefer the side with more room between the obstacles and the table edge, try the other next.
  double room[2];
  for (int k = 0; k < 2; ++k) {
    const double sg = k == 0 ? 1.0 : -1.0;
    room[k] = 0.0;
    for (double t = 0.0; t < 1.0; t += 0.05) {
      const Point2D p{o.x + sg * n.x * t, o.y + sg * n.y * t};
      if (!fits(p)) break;
      room[k] = t;
    }
  }
  const int order[2] = {room[0] >= room[1] ? 0 : 1, room[0] >= room[1] ? 1 : 0};
  for (int k : order) {
    const double sg = k == 0 ? 1.0 : -1.0;
    const Point2D w1{o.x - u.x * ahead + sg * n.x * side, o.y - u.y * ahead + sg * n.y * side};
    const Point2D w2{o.x + u.x * ahead + sg * n.x * side, o.y + u.y * ahead + sg * n.y * side};
    if (!fits(w1) || !fits(w2)) continue;
    bool clear = true;  // no obstacle may sit on the detour itself (the leg w1 -> w2)
    const double len = std::hypot(w2.x - w1.x, w2.y - w1.y);
    for (const auto& q : obstacles) {
      const double t = std::clamp(((q.x - w1.x) * (w2.x - w1.x) + (q.y - w1.y) * (w2.y - w1.y)) / (len * len), 0.0, 1.0);
      if (std::hypot(w1.x + t * (w2.x - w1.x) - q.x, w1.y + t * (w2.y - w1.y) - q.y) < config_.clearance()) clear = false;
    }
    if (!clear) continue;
    *waypoints = {w1, w2};
    return true;
  }
  return false;
}

}  // namespace driver
}  // namespace hal_nodes
